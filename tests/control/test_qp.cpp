// The dense QP of the inverse controller against independent answers: closed forms,
// brute-force enumeration of active sets, degenerate and infeasible problems, scaling.
#include <gtest/gtest.h>

#include <random>

#include "control/qp.hpp"

namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

double objective(const MatrixXd& H, const VectorXd& f, const VectorXd& x) {
  return 0.5 * x.dot(H * x) + f.dot(x);
}

// Reference: every subset S of at most n rows, solved as equalities (KKT system); the
// feasible one with multipliers >= 0 is the optimum of a strictly convex QP.
struct BruteForce {
  VectorXd x;
  double value = std::numeric_limits<double>::infinity();
  bool feasible = false;
};

BruteForce brute_force(const MatrixXd& H, const VectorXd& f, const MatrixXd& A, const VectorXd& b) {
  const int n = static_cast<int>(f.size()), m = static_cast<int>(b.size());
  BruteForce best;
  for (int mask = 0; mask < (1 << m); ++mask) {
    std::vector<int> S;
    for (int i = 0; i < m; ++i)
      if (mask & (1 << i)) S.push_back(i);
    if (static_cast<int>(S.size()) > n) continue;
    const int k = static_cast<int>(S.size());
    MatrixXd K = MatrixXd::Zero(n + k, n + k);
    VectorXd rhs(n + k);
    K.topLeftCorner(n, n) = H;
    rhs.head(n) = -f;
    for (int j = 0; j < k; ++j) {
      K.block(0, n + j, n, 1) = -A.row(S[j]).transpose();
      K.block(n + j, 0, 1, n) = A.row(S[j]);
      rhs(n + j) = b(S[j]);
    }
    Eigen::FullPivLU<MatrixXd> lu(K);
    if (lu.rank() < n + k) continue;
    const VectorXd sol = lu.solve(rhs);
    const VectorXd x = sol.head(n);
    if ((A * x - b).minCoeff() < -1e-9) continue;
    if (k > 0 && sol.tail(k).minCoeff() < -1e-9) continue;
    const double v = objective(H, f, x);
    if (v < best.value) best = {x, v, true};
  }
  return best;
}

MatrixXd random_spd(int n, std::mt19937& rng) {
  std::normal_distribution<double> g;
  MatrixXd M(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) M(i, j) = g(rng);
  return M * M.transpose() + 0.1 * MatrixXd::Identity(n, n);
}

TEST(Qp, UnconstrainedIsTheNewtonStep) {
  MatrixXd H(2, 2);
  H << 4, 1, 1, 3;
  VectorXd f(2);
  f << 1, 2;
  const hs::QpResult r = hs::solve_qp(H, f, MatrixXd(0, 2), VectorXd(0));
  ASSERT_TRUE(r.solved) << r.status;
  // -H^-1 f = -(1/11) [3 -1; -1 4] [1; 2] = [-1/11, -7/11]
  EXPECT_NEAR(r.x(0), -1.0 / 11, 1e-15);
  EXPECT_NEAR(r.x(1), -7.0 / 11, 1e-15);
  EXPECT_TRUE(r.active.empty());
  EXPECT_EQ(r.iterations, 0);
}

TEST(Qp, DiagonalBoxIsAClamp) {
  // Separable: x_i = clamp(-f_i / h_i, lo_i, hi_i), multiplier h_i |x_i - free_i| on the
  // active bound.
  const VectorXd h = (VectorXd(4) << 1, 2, 3, 4).finished();
  const VectorXd f = (VectorXd(4) << -5, 1, 0.3, 8).finished();
  const VectorXd lo = (VectorXd(4) << -1, -1, -1, -1).finished();
  const VectorXd hi = (VectorXd(4) << 2, 2, 2, 2).finished();
  MatrixXd A = MatrixXd::Zero(8, 4);
  VectorXd b(8);
  for (int i = 0; i < 4; ++i) {
    A(2 * i, i) = 1;  // x_i >= lo_i
    b(2 * i) = lo(i);
    A(2 * i + 1, i) = -1;  // -x_i >= -hi_i
    b(2 * i + 1) = -hi(i);
  }
  const hs::QpResult r = hs::solve_qp(h.asDiagonal(), f, A, b);
  ASSERT_TRUE(r.solved) << r.status;
  for (int i = 0; i < 4; ++i) {
    const double free = -f(i) / h(i);
    EXPECT_NEAR(r.x(i), std::clamp(free, lo(i), hi(i)), 1e-14) << i;
  }
  // x_0 = 5 -> 2 (upper, row 1), x_3 = -2 -> -1 (lower, row 6); x_1, x_2 free.
  EXPECT_EQ(r.active, (std::vector<int>{1, 6}));
  EXPECT_NEAR(r.multipliers(1), 1 * (5 - 2), 1e-13);
  EXPECT_NEAR(r.multipliers(6), 4 * (-1 + 2), 1e-13);
  EXPECT_LT(r.kkt_residual, 1e-14);
}

TEST(Qp, BoundMetAtZeroHasASmallResidual) {
  // The controller's usual saturation: pressure at its bound, so b = 0 and x = 0; the
  // residual is measured against the size of the step the bound stopped (|H^-1 f| = 2.5).
  MatrixXd H(2, 2);
  H << 2, 0.5, 0.5, 1;
  const VectorXd f = (VectorXd(2) << 5, 1).finished();
  MatrixXd A(1, 2);
  A << 1, 0;
  const hs::QpResult r = hs::solve_qp(H, f, A, VectorXd::Zero(1));
  ASSERT_TRUE(r.solved);
  EXPECT_EQ(r.x(0), 0.0);
  EXPECT_NEAR(r.x(1), -1.0, 1e-15);  // min over x1 of 1/2 x1^2 + x1 at x0 = 0
  EXPECT_NEAR(r.multipliers(0), 5 - 0.5, 1e-14);
  EXPECT_LT(r.kkt_residual, 1e-14);
}

TEST(Qp, ProjectionOnAHalfPlane) {
  // min 1/2 |x - c|^2 s.t. a.x >= beta: x = c + (beta - a.c) a / |a|^2 when violated.
  const VectorXd c = (VectorXd(3) << 1, -2, 0.5).finished();
  const VectorXd a = (VectorXd(3) << 1, 2, -2).finished();
  const double beta = 4;
  const hs::QpResult r =
      hs::solve_qp(MatrixXd::Identity(3, 3), -c, a.transpose(), VectorXd::Constant(1, beta));
  ASSERT_TRUE(r.solved);
  const VectorXd expected = c + (beta - a.dot(c)) / a.squaredNorm() * a;
  EXPECT_LT((r.x - expected).norm(), 1e-14);
  EXPECT_NEAR(r.multipliers(0), (beta - a.dot(c)) / a.squaredNorm(), 1e-14);
}

TEST(Qp, MatchesBruteForceOnRandomProblems) {
  std::mt19937 rng(7);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> u(0, 1);
  int constrained = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const int n = 1 + trial % 4;
    const int m = 1 + (trial / 4) % 8;
    const MatrixXd H = random_spd(n, rng);
    VectorXd f(n), x0(n);
    for (int i = 0; i < n; ++i) f(i) = 3 * g(rng), x0(i) = g(rng);
    MatrixXd A(m, n);
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < n; ++j) A(i, j) = g(rng);
    // Feasible by construction: x0 satisfies every row with slack in (0, 1).
    VectorXd b = A * x0;
    for (int i = 0; i < m; ++i) b(i) -= u(rng);
    const BruteForce ref = brute_force(H, f, A, b);
    ASSERT_TRUE(ref.feasible) << "trial " << trial;
    const hs::QpResult r = hs::solve_qp(H, f, A, b);
    ASSERT_TRUE(r.solved) << "trial " << trial << ": " << r.status;
    EXPECT_LT((r.x - ref.x).norm(), 1e-9 * (1 + ref.x.norm())) << "trial " << trial;
    EXPECT_NEAR(objective(H, f, r.x), ref.value, 1e-10 * (1 + std::abs(ref.value)));
    EXPECT_LT(r.kkt_residual, 1e-12) << "trial " << trial;
    EXPECT_GE(r.multipliers.minCoeff(), 0.0);
    constrained += !r.active.empty();
  }
  // The generator must exercise the constraints, not only the unconstrained minimum.
  EXPECT_GT(constrained, 200);
}

TEST(Qp, DegenerateVertexAndDuplicateRows) {
  // Three lines through (1, 1) (x >= 1, y >= 1, x + y >= 2), one of them twice; the
  // target (0, 0) is pulled to the vertex, where the active normals are dependent.
  MatrixXd A(4, 2);
  A << 1, 0, 0, 1, 1, 1, 1, 1;
  const VectorXd b = (VectorXd(4) << 1, 1, 2, 2).finished();
  const hs::QpResult r = hs::solve_qp(MatrixXd::Identity(2, 2), VectorXd::Zero(2), A, b);
  ASSERT_TRUE(r.solved) << r.status;
  EXPECT_NEAR(r.x(0), 1, 1e-14);
  EXPECT_NEAR(r.x(1), 1, 1e-14);
  EXPECT_LE(r.active.size(), 2u);  // an independent subset is enough
  // Stationarity: x - 0 = A^T mu with mu >= 0 (not unique; the residual says it holds).
  EXPECT_LT(r.kkt_residual, 1e-14);
}

TEST(Qp, EqualityAsTwoOppositeRows) {
  // x0 + x1 = 1 written as >= and <=; min 1/2 |x|^2 -> (1/2, 1/2).
  MatrixXd A(2, 2);
  A << 1, 1, -1, -1;
  const VectorXd b = (VectorXd(2) << 1, -1).finished();
  const hs::QpResult r = hs::solve_qp(MatrixXd::Identity(2, 2), VectorXd::Zero(2), A, b);
  ASSERT_TRUE(r.solved) << r.status;
  EXPECT_NEAR(r.x(0), 0.5, 1e-15);
  EXPECT_NEAR(r.x(1), 0.5, 1e-15);
}

TEST(Qp, InfeasibleBoundsAreReported) {
  // x >= 1 and x <= 0.
  MatrixXd A(2, 1);
  A << 1, -1;
  const VectorXd b = (VectorXd(2) << 1, 0).finished();
  const hs::QpResult r = hs::solve_qp(MatrixXd::Identity(1, 1), VectorXd::Zero(1), A, b);
  EXPECT_FALSE(r.solved);
  EXPECT_NE(r.status.find("infeasible"), std::string::npos) << r.status;
  // A zero row asking 0 >= 1.
  const hs::QpResult z = hs::solve_qp(MatrixXd::Identity(2, 2), VectorXd::Zero(2),
                                      MatrixXd::Zero(1, 2), VectorXd::Ones(1));
  EXPECT_FALSE(z.solved);
  EXPECT_NE(z.status.find("row 0"), std::string::npos) << z.status;
}

TEST(Qp, InvariantUnderScalingOfObjectiveAndRows) {
  // The controller's W spans many decades (metres per pascal): the answer must not move
  // when the objective and each row are scaled.
  std::mt19937 rng(3);
  std::normal_distribution<double> g;
  const int n = 3, m = 6;
  const MatrixXd H = random_spd(n, rng);
  VectorXd f(n);
  for (int i = 0; i < n; ++i) f(i) = 5 * g(rng);
  MatrixXd A(m, n);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < n; ++j) A(i, j) = g(rng);
  const VectorXd b = -VectorXd::Ones(m) * 0.3;
  const hs::QpResult ref = hs::solve_qp(H, f, A, b);
  ASSERT_TRUE(ref.solved);
  ASSERT_FALSE(ref.active.empty());
  VectorXd rows(m);
  rows << 1e-6, 1e3, 1, 1e8, 1e-9, 7;
  const hs::QpResult s =
      hs::solve_qp(1e-12 * H, 1e-12 * f, rows.asDiagonal() * A, rows.asDiagonal() * b);
  ASSERT_TRUE(s.solved) << s.status;
  EXPECT_LT((s.x - ref.x).norm(), 1e-10 * ref.x.norm());
  EXPECT_EQ(s.active, ref.active);
  EXPECT_LT(s.kkt_residual, 1e-12);
}

TEST(Qp, BadDataIsRefusedWithAReason) {
  const MatrixXd I = MatrixXd::Identity(2, 2);
  VectorXd f = VectorXd::Zero(2);
  f(1) = std::nan("");
  EXPECT_FALSE(hs::solve_qp(I, f, MatrixXd(0, 2), VectorXd(0)).solved);
  EXPECT_NE(hs::solve_qp(I, f, MatrixXd(0, 2), VectorXd(0)).status.find("non-finite"),
            std::string::npos);
  MatrixXd indefinite(2, 2);
  indefinite << 1, 0, 0, -1;
  const hs::QpResult r = hs::solve_qp(indefinite, VectorXd::Zero(2), MatrixXd(0, 2), VectorXd(0));
  EXPECT_FALSE(r.solved);
  EXPECT_EQ(r.status, "H is not positive definite");
  EXPECT_THROW(hs::solve_qp(I, VectorXd::Zero(3), MatrixXd(0, 3), VectorXd(0)),
               std::invalid_argument);
}

}  // namespace
