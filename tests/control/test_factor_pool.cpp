// The background factorizations' sequential part: CHOLMOD's factorization of a CSR matrix
// solves it (against a closed form), a matrix that is not positive definite is refused with
// the reason, and the thread pool returns each factorization with the state it was given.
#include <gtest/gtest.h>

#include <cmath>

#include "control/factor_pool.hpp"

namespace {

// The 1D Laplacian tridiag(-1, 2, -1) of size n, plus `shift` on the diagonal.
hs::CsrMatrix laplacian(int n, double shift = 0) {
  hs::CsrMatrix A;
  A.n = n;
  A.row_start.push_back(0);
  for (int i = 0; i < n; ++i) {
    for (int j = std::max(i - 1, 0); j <= std::min(i + 1, n - 1); ++j) {
      A.column.push_back(j);
      A.value.push_back(i == j ? 2 + shift : -1);
    }
    A.row_start.push_back(static_cast<int>(A.column.size()));
  }
  return A;
}

TEST(FactorPool, CholeskySolvesTheLaplacian) {
  // -u'' = 1 on (0, 1), u(0) = u(1) = 0, on n interior points: the discrete solution is the
  // exact u = x (1 - x) / 2 at the nodes (second differences are exact on quadratics).
  const int n = 200;
  const double h = 1.0 / (n + 1);
  hs::CholeskyAnalysis analysis;
  std::string error;
  auto f = analysis.factor(laplacian(n), &error);
  ASSERT_TRUE(f) << error;
  std::vector<double> b(n, h * h), x(n);
  f->solve(b.data(), x.data());
  for (int i = 0; i < n; ++i) {
    const double xi = (i + 1) * h;
    EXPECT_NEAR(x[i], xi * (1 - xi) / 2, 1e-12) << i;
  }
}

TEST(FactorPool, IndefiniteMatrixIsRefusedWithTheReason) {
  // The Laplacian's smallest eigenvalue is 2 - 2 cos(pi / (n + 1)) > 0; shifted by -1 the
  // matrix has eigenvalues on both sides of 0.
  hs::CholeskyAnalysis analysis;
  std::string error;
  EXPECT_FALSE(analysis.factor(laplacian(50, -1.0), &error));
  EXPECT_NE(error.find("not positive definite"), std::string::npos) << error;
  // The same analysis still factors a positive definite matrix of that pattern.
  EXPECT_TRUE(analysis.factor(laplacian(50, 0.5), &error));
}

TEST(FactorPool, ThreadsReturnEachFactorizationWithItsState) {
  hs::FactorPool pool(2);
  hs::CsrMatrix good = laplacian(100), bad = laplacian(100, -1.0), third = laplacian(100);
  EXPECT_TRUE(pool.submit(good, 7));
  EXPECT_TRUE(pool.submit(bad, 8));
  pool.wait_idle();
  auto done = pool.take_finished();
  ASSERT_EQ(done.size(), 2u);
  for (auto& r : done) {
    if (r.state == 7) {
      ASSERT_TRUE(r.factor) << r.error;
      std::vector<double> b(100, 1.0), x(100);
      r.factor->solve(b.data(), x.data());
      // A x = 1 with x_i = (i + 1)(n - i) / 2, the discrete parabola of size n = 100.
      for (int i = 0; i < 100; ++i) EXPECT_NEAR(x[i], (i + 1) * (100.0 - i) / 2, 1e-9);
    } else {
      EXPECT_EQ(r.state, 8);
      EXPECT_FALSE(r.factor);
      EXPECT_FALSE(r.error.empty());
    }
  }
  EXPECT_TRUE(pool.submit(third, 9));
}

}  // namespace
