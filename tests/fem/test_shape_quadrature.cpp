// Shape functions (partition of unity, Kronecker property, gradients against finite
// differences, quadratic reproduction) and quadrature exactness on monomials.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "common/error.hpp"
#include "fem/quadrature.hpp"
#include "fem/shape.hpp"

namespace hs {
namespace {

double factorial(int n) { return n <= 1 ? 1.0 : n * factorial(n - 1); }

// int over the reference tetrahedron of x^a y^b z^c = a! b! c! / (a + b + c + 3)!
double tet_monomial_integral(int a, int b, int c) {
  return factorial(a) * factorial(b) * factorial(c) / factorial(a + b + c + 3);
}

// int over the reference triangle of x^a y^b = a! b! / (a + b + 2)!
double tri_monomial_integral(int a, int b) {
  return factorial(a) * factorial(b) / factorial(a + b + 2);
}

Eigen::Vector3d random_tet_point(std::mt19937& rng) {
  std::uniform_real_distribution<double> d(0.0, 1.0);
  for (;;) {
    const Eigen::Vector3d p(d(rng), d(rng), d(rng));
    if (p.sum() <= 1.0) return p;
  }
}

TEST(TetQuadrature, IntegratesMonomialsUpToItsDegreeExactly) {
  for (int degree = 0; degree <= kMaxQuadratureDegree; ++degree) {
    const TetQuadrature& q = tet_quadrature(degree);
    for (const auto& p : q.points) {  // points inside the element
      EXPECT_GT(p.minCoeff(), 0.0);
      EXPECT_LT(p.sum(), 1.0);
    }
    for (int a = 0; a <= degree; ++a)
      for (int b = 0; a + b <= degree; ++b)
        for (int c = 0; a + b + c <= degree; ++c) {
          double sum = 0;
          for (size_t i = 0; i < q.points.size(); ++i)
            sum += q.weights[i] * std::pow(q.points[i](0), a) * std::pow(q.points[i](1), b) *
                   std::pow(q.points[i](2), c);
          const double exact = tet_monomial_integral(a, b, c);
          EXPECT_NEAR(sum, exact, 1e-13 * exact)
              << "degree " << degree << " monomial " << a << " " << b << " " << c;
        }
  }
}

TEST(TetQuadrature, PointCountsOfTheNamedRules) {
  EXPECT_EQ(tet_quadrature(1).points.size(), 1u);
  EXPECT_EQ(tet_quadrature(2).points.size(), 4u);
  EXPECT_EQ(tet_quadrature(7).points.size(), 64u);  // 4 Gauss-Jacobi points per direction
  EXPECT_THROW(tet_quadrature(kMaxQuadratureDegree + 1), std::invalid_argument);
}

TEST(TriQuadrature, IntegratesMonomialsUpToItsDegreeExactly) {
  for (int degree = 0; degree <= kMaxQuadratureDegree; ++degree) {
    const TriQuadrature& q = tri_quadrature(degree);
    for (int a = 0; a <= degree; ++a)
      for (int b = 0; a + b <= degree; ++b) {
        double sum = 0;
        for (size_t i = 0; i < q.points.size(); ++i)
          sum += q.weights[i] * std::pow(q.points[i](0), a) * std::pow(q.points[i](1), b);
        const double exact = tri_monomial_integral(a, b);
        EXPECT_NEAR(sum, exact, 1e-13 * exact)
            << "degree " << degree << " monomial " << a << " " << b;
      }
  }
}

TEST(GaussJacobi, FiveDegreeNineOnWeightOneMinusXSquared) {
  // int_0^1 (1 - x)^2 x^k dx = 2 / ((k + 1)(k + 2)(k + 3))
  std::vector<double> x, w;
  gauss_jacobi(5, 2, x, w);
  for (int k = 0; k <= 9; ++k) {
    double sum = 0;
    for (int i = 0; i < 5; ++i) sum += w[i] * std::pow(x[i], k);
    EXPECT_NEAR(sum, 2.0 / ((k + 1.0) * (k + 2.0) * (k + 3.0)), 1e-15) << k;
  }
}

class TetShape : public ::testing::TestWithParam<int> {};

TEST_P(TetShape, PartitionOfUnityAndKronecker) {
  const int order = GetParam(), n = tet_num_nodes(order);
  std::mt19937 rng(1);
  double N[10], dN[30];
  for (int trial = 0; trial < 20; ++trial) {
    tet_shape(order, random_tet_point(rng), N, dN);
    double sum = 0;
    Eigen::Vector3d grad_sum = Eigen::Vector3d::Zero();
    for (int a = 0; a < n; ++a) {
      sum += N[a];
      grad_sum += Eigen::Vector3d(dN[3 * a], dN[3 * a + 1], dN[3 * a + 2]);
    }
    EXPECT_NEAR(sum, 1.0, 1e-14);
    EXPECT_LT(grad_sum.norm(), 1e-13);
  }
  for (int b = 0; b < n; ++b) {
    tet_shape(order, tet_node(order, b), N, nullptr);
    for (int a = 0; a < n; ++a) EXPECT_NEAR(N[a], a == b ? 1.0 : 0.0, 1e-15) << a << " at " << b;
  }
}

TEST_P(TetShape, GradientsMatchFiniteDifferences) {
  const int order = GetParam(), n = tet_num_nodes(order);
  std::mt19937 rng(2);
  const double h = 1e-6;
  double N[10], dN[30], Np[10], Nm[10];
  for (int trial = 0; trial < 10; ++trial) {
    const Eigen::Vector3d xi = random_tet_point(rng);
    tet_shape(order, xi, N, dN);
    for (int d = 0; d < 3; ++d) {
      const Eigen::Vector3d e = h * Eigen::Vector3d::Unit(d);
      tet_shape(order, xi + e, Np, nullptr);
      tet_shape(order, xi - e, Nm, nullptr);
      for (int a = 0; a < n; ++a) EXPECT_NEAR(dN[3 * a + d], (Np[a] - Nm[a]) / (2 * h), 1e-9);
    }
  }
}

TEST_P(TetShape, InterpolatesPolynomialsOfItsOrderExactly) {
  const int order = GetParam(), n = tet_num_nodes(order);
  // A full polynomial of the element's degree: every linear and (P2) quadratic monomial.
  auto f = [order](const Eigen::Vector3d& p) {
    double v = 0.7 - 1.3 * p(0) + 2.1 * p(1) + 0.4 * p(2);
    if (order == 2)
      v += 0.9 * p(0) * p(0) - 1.7 * p(1) * p(1) + 0.6 * p(2) * p(2) + 1.1 * p(0) * p(1) -
           0.8 * p(1) * p(2) + 2.3 * p(2) * p(0);
    return v;
  };
  std::mt19937 rng(3);
  double N[10];
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Vector3d xi = random_tet_point(rng);
    tet_shape(order, xi, N, nullptr);
    double interpolated = 0;
    for (int a = 0; a < n; ++a) interpolated += N[a] * f(tet_node(order, a));
    EXPECT_NEAR(interpolated, f(xi), 1e-13);
  }
}

INSTANTIATE_TEST_SUITE_P(Orders, TetShape, ::testing::Values(1, 2));

class TriShape : public ::testing::TestWithParam<int> {};

TEST_P(TriShape, PartitionOfUnityKroneckerAndGradients) {
  const int order = GetParam(), n = tri_num_nodes(order);
  double N[6], dN[12], Np[6], Nm[6];
  for (int b = 0; b < n; ++b) {
    tri_shape(order, tri_node(order, b), N, nullptr);
    for (int a = 0; a < n; ++a) EXPECT_NEAR(N[a], a == b ? 1.0 : 0.0, 1e-15) << a << " at " << b;
  }
  const double h = 1e-6;
  for (const Eigen::Vector2d& xi : {Eigen::Vector2d(0.2, 0.3), Eigen::Vector2d(0.6, 0.1)}) {
    tri_shape(order, xi, N, dN);
    double sum = 0;
    for (int a = 0; a < n; ++a) sum += N[a];
    EXPECT_NEAR(sum, 1.0, 1e-14);
    for (int d = 0; d < 2; ++d) {
      const Eigen::Vector2d e = h * Eigen::Vector2d::Unit(d);
      tri_shape(order, xi + e, Np, nullptr);
      tri_shape(order, xi - e, Nm, nullptr);
      for (int a = 0; a < n; ++a) EXPECT_NEAR(dN[2 * a + d], (Np[a] - Nm[a]) / (2 * h), 1e-9);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Orders, TriShape, ::testing::Values(1, 2));

TEST(Shape, UnsupportedOrderIsAnInputError) {
  EXPECT_THROW(tet_num_nodes(3), InputError);
  EXPECT_THROW(tri_num_nodes(0), InputError);
}

}  // namespace
}  // namespace hs
