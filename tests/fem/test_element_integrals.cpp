// Volume, body force, mass matrix and output fields of P1/P2 tetrahedra against closed forms,
// including a curved P2 element whose geometry is a known quadratic map.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>
#include <random>

#include "element_fixtures.hpp"
#include "fem/element.hpp"
#include "fem/shape.hpp"
#include "materials/registry.hpp"

namespace hs {
namespace {

using namespace testing_fixtures;

const Eigen::Matrix3d kA =
    (Eigen::Matrix3d() << 1.2, 0.3, -0.1, 0.1, 0.9, 0.2, -0.2, 0.1, 1.1).finished();
const Eigen::Vector3d kShift(0.4, -0.3, 1.0);

// Element nodes X_a = A phi(xi_a) + b with phi(xi) = xi + c xi_0^2 e_0: the P2 interpolation
// reproduces this quadratic map, det(dX/dxi) = det A (1 + 2 c xi_0) and the volume is
// det A (1/6 + c/12). With c = 0 (or P1) the element is straight.
std::vector<double> mapped_tet(int order, double c) {
  std::vector<double> X;
  for (int a = 0; a < tet_num_nodes(order); ++a) {
    Eigen::Vector3d xi = tet_node(order, a);
    xi(0) += c * xi(0) * xi(0);
    const Eigen::Vector3d x = kA * xi + kShift;
    X.insert(X.end(), {x(0), x(1), x(2)});
  }
  return X;
}

double mapped_volume(double c) { return kA.determinant() * (1.0 / 6.0 + c / 12.0); }

TEST(Volume, StraightAndCurvedElements) {
  EXPECT_NEAR(tet_volume(1, mapped_tet(1, 0).data()), mapped_volume(0), 1e-15);
  EXPECT_NEAR(tet_volume(2, mapped_tet(2, 0).data()), mapped_volume(0), 1e-15);
  EXPECT_NEAR(tet_volume(2, mapped_tet(2, 0.3).data()), mapped_volume(0.3), 1e-15);
}

TEST(BodyForce, ClosedFormOnStraightElements) {
  // int N_a dV: V/4 on P1; on P2 -V/20 at the vertices and V/5 at the edge nodes.
  const double rho = 2.5, V = mapped_volume(0);
  const std::array<double, 3> g = {0.0, -9.81, 1.0};
  for (int order : {1, 2}) {
    const int npe = tet_num_nodes(order);
    std::vector<double> f(3 * npe);
    tet_body_force(order, mapped_tet(order, 0).data(), rho, g, f.data());
    for (int a = 0; a < npe; ++a) {
      const double share = order == 1 ? 0.25 : (a < 4 ? -1.0 / 20 : 1.0 / 5);
      for (int i = 0; i < 3; ++i) EXPECT_NEAR(f[3 * a + i], rho * g[i] * V * share, 1e-14);
    }
  }
}

TEST(BodyForce, SumsToTheWeightOfACurvedElement) {
  const double rho = 2.5, c = 0.3;
  const std::array<double, 3> g = {0.5, -9.81, 1.0};
  std::vector<double> f(30);
  tet_body_force(2, mapped_tet(2, c).data(), rho, g, f.data());
  for (int i = 0; i < 3; ++i) {
    double total = 0;
    for (int a = 0; a < 10; ++a) total += f[3 * a + i];
    EXPECT_NEAR(total, rho * g[i] * mapped_volume(c), 1e-13);
  }
}

// int over a straight tetrahedron of N_a N_b, from the shape functions written as polynomials
// in the barycentric coordinates and int L0^p L1^q L2^r L3^s dV = 6 V p! q! r! s! / (p+q+r+s+3)!.
double reference_mass(int order, int a, int b, double V) {
  using Monomial = std::array<int, 4>;
  using Polynomial = std::map<Monomial, double>;
  auto shape = [order](int node) {
    Polynomial p;
    if (node < 4) {
      Monomial m1{}, m2{};
      m1[node] = 1;
      m2[node] = 2;
      if (order == 1) return Polynomial{{m1, 1.0}};
      return Polynomial{{m2, 2.0}, {m1, -1.0}};
    }
    Monomial m{};
    m[kTetEdges[node - 4][0]] = 1;
    m[kTetEdges[node - 4][1]] = 1;
    return Polynomial{{m, 4.0}};
  };
  auto factorial = [](int n) {
    double f = 1;
    for (int k = 2; k <= n; ++k) f *= k;
    return f;
  };
  double integral = 0;
  for (const auto& [ma, ca] : shape(a))
    for (const auto& [mb, cb] : shape(b)) {
      double num = 6 * V;
      int total = 0;
      for (int v = 0; v < 4; ++v) {
        num *= factorial(ma[v] + mb[v]);
        total += ma[v] + mb[v];
      }
      integral += ca * cb * num / factorial(total + 3);
    }
  return integral;
}

TEST(Mass, MatchesBarycentricIntegralsOnStraightElements) {
  const double rho = 1.7, V = mapped_volume(0);
  for (int order : {1, 2}) {
    const int npe = tet_num_nodes(order), n = 3 * npe;
    std::vector<double> M(n * n);
    tet_mass(order, mapped_tet(order, 0).data(), rho, M.data());
    for (int a = 0; a < npe; ++a)
      for (int b = 0; b < npe; ++b)
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) {
            const double expected = i == j ? rho * reference_mass(order, a, b, V) : 0.0;
            EXPECT_NEAR(M[(3 * a + i) * n + 3 * b + j], expected, 1e-15)
                << "order " << order << " nodes " << a << " " << b;
          }
  }
  // The classical P1 mass matrix rho V / 20 (1 + delta_ab), as a check of the reference.
  EXPECT_NEAR(reference_mass(1, 0, 0, 1.0), 2.0 / 20, 1e-15);
  EXPECT_NEAR(reference_mass(1, 0, 3, 1.0), 1.0 / 20, 1e-15);
}

TEST(Mass, SumsToTheMassOfACurvedElementPerDirection) {
  const double rho = 1.7, c = 0.3;
  std::vector<double> M(900);
  tet_mass(2, mapped_tet(2, c).data(), rho, M.data());
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double total = 0;
      for (int a = 0; a < 10; ++a)
        for (int b = 0; b < 10; ++b) total += M[(3 * a + i) * 30 + 3 * b + j];
      EXPECT_NEAR(total, i == j ? rho * mapped_volume(c) : 0.0, 1e-13);
    }
}

TEST(Fields, UniaxialStretchOfACurvedElement) {
  // u = H X with H = diag(e, 0, 0): F = diag(1 + e, 1, 1) everywhere, also on a curved P2.
  const double e = 0.1;
  const auto linear = make_material_law("linear_elastic", {{"mu", 3.0}, {"lambda", 7.0}});
  const auto nh = make_material_law("neo_hookean", {{"mu", 3.0}, {"lambda", 7.0}});
  for (int order : {1, 2}) {
    const std::vector<double> X = mapped_tet(order, order == 2 ? 0.3 : 0.0);
    std::vector<double> u(X.size(), 0.0);
    for (size_t a = 0; a < X.size() / 3; ++a) u[3 * a] = e * X[3 * a];
    // Linear: sigma = diag(lambda + 2 mu, lambda, lambda) e, von Mises 2 mu e.
    const ElementFields fl = tet_fields(order, X.data(), u.data(), *linear);
    EXPECT_NEAR(fl.von_mises, 2 * linear->elastic_constants().mu * e, 1e-13);
    EXPECT_NEAR(fl.J, 1 + e, 1e-14);
    // Neo-Hookean: sigma_i = (mu (l_i^2 - 1) + lambda ln J) / J, von Mises |sigma_1 - sigma_2|.
    const double J = 1 + e;
    const double expected = nh->elastic_constants().mu * (J * J - 1) / J;
    EXPECT_NEAR(tet_fields(order, X.data(), u.data(), *nh).von_mises, expected, 1e-13);
  }
}

// u = H X for a homogeneous H: F = I + H on every element, straight or curved.
std::vector<double> homogeneous_displacement(const std::vector<double>& X, const Mat3& H) {
  std::vector<double> u(X.size());
  for (size_t a = 0; a < X.size() / 3; ++a) {
    const Eigen::Vector3d ua = H * Eigen::Vector3d(X[3 * a], X[3 * a + 1], X[3 * a + 2]);
    for (int d = 0; d < 3; ++d) u[3 * a + d] = ua(d);
  }
  return u;
}

double largest_difference(const Mat3& a, const Mat3& b) { return (a - b).cwiseAbs().maxCoeff(); }

TEST(Fields, NeoHookeanStressAndStrainOfAHomogeneousDeformation) {
  // A stretch with shear: the closed form of the law, sigma = (mu (b - I) + lambda ln J I) / J
  // with b = F F^T, and E = (F^T F - I) / 2, on straight and curved elements, for the
  // standard and the F-bar element (Jbar = J when the deformation is homogeneous).
  const double mu = 3.0e5, lambda = 7.0e5;
  const auto nh = make_material_law("neo_hookean", {{"mu", mu}, {"lambda", lambda}});
  const Mat3 H = (Mat3() << 0.2, 0.05, 0.0, -0.03, -0.08, 0.1, 0.02, 0.0, -0.06).finished();
  const Mat3 F = Mat3::Identity() + H;
  const double J = F.determinant();
  const Mat3 sigma =
      (mu * (F * F.transpose() - Mat3::Identity()) + lambda * std::log(J) * Mat3::Identity()) / J;
  const Mat3 E = 0.5 * (F.transpose() * F - Mat3::Identity());
  for (int order : {1, 2}) {
    const std::vector<double> X = mapped_tet(order, order == 2 ? 0.3 : 0.0);
    const std::vector<double> u = homogeneous_displacement(X, H);
    for (const ElementFields& f : {tet_fields(order, X.data(), u.data(), *nh),
                                   tet_fields_fbar(order, X.data(), u.data(), *nh)}) {
      EXPECT_LT(largest_difference(f.stress, sigma), 1e-12 * sigma.norm()) << "order " << order;
      EXPECT_LT(largest_difference(f.strain, E), 1e-13) << "order " << order;
      EXPECT_NEAR(f.J, J, 1e-13);
    }
  }
}

TEST(Fields, UniaxialStretchStressAndPrincipalValues) {
  // F = diag(1 + e, 1, 1): sigma_1 = (mu (l^2 - 1) + lambda ln l) / l, sigma_2 = sigma_3 =
  // lambda ln l / l; E_11 = ((1 + e)^2 - 1) / 2, the other strains 0. Principal values come
  // largest first.
  const double mu = 3.0, lambda = 7.0, e = 0.25, l = 1 + e;
  const auto nh = make_material_law("neo_hookean", {{"mu", mu}, {"lambda", lambda}});
  const Mat3 H = Eigen::Vector3d(e, 0, 0).asDiagonal();
  const std::vector<double> X = mapped_tet(2, 0.3);
  const ElementFields f = tet_fields(2, X.data(), homogeneous_displacement(X, H).data(), *nh);
  const double s1 = (mu * (l * l - 1) + lambda * std::log(l)) / l, s2 = lambda * std::log(l) / l;
  const Mat3 sigma = Eigen::Vector3d(s1, s2, s2).asDiagonal();
  EXPECT_LT(largest_difference(f.stress, sigma), 1e-13);
  EXPECT_NEAR(f.strain(0, 0), (l * l - 1) / 2, 1e-15);
  EXPECT_NEAR(f.strain.norm() - std::abs(f.strain(0, 0)), 0, 1e-15);
  const auto ps = principal_values(f.stress), pe = principal_values(f.strain);
  EXPECT_NEAR(ps[0], s1, 1e-13);
  EXPECT_NEAR(ps[1], s2, 1e-13);
  EXPECT_NEAR(ps[2], s2, 1e-13);
  EXPECT_NEAR(pe[0], (l * l - 1) / 2, 1e-15);
  EXPECT_NEAR(pe[1], 0, 1e-15);
  EXPECT_NEAR(pe[2], 0, 1e-15);
}

// Principal values of Q diag(l) Q^T for random rotations Q and scales, the two upper values
// from far apart to equal: each within 1e-12 of the largest, largest first (the closed form
// alone lost 1e-8 at equal values).
TEST(Fields, PrincipalValuesAreTheEigenvaluesAtEveryGap) {
  std::mt19937 random(7);
  std::normal_distribution<double> normal;
  for (double gap : {0.5, 1e-2, 1.1e-3, 0.9e-3, 1e-6, 1e-10, 0.0})
    for (int k = 0; k < 200; ++k) {
      Mat3 m;
      for (int i = 0; i < 9; ++i) m(i / 3, i % 3) = normal(random);
      const Mat3 Q = Eigen::HouseholderQR<Mat3>(m).householderQ();
      const double scale = std::pow(10.0, k % 13 - 6);
      const Eigen::Vector3d l(1 + gap, 1, -0.5);
      Mat3 A = scale * Q * l.asDiagonal() * Q.transpose();
      A = 0.5 * (A + A.transpose());
      const auto p = principal_values(A);
      for (int i = 0; i < 3; ++i)
        EXPECT_NEAR(p[i], scale * l[i], 1e-12 * scale) << "gap " << gap << " case " << k;
    }
}

TEST(Fields, LinearElasticStressIsLameOfTheSmallStrain) {
  // sigma = lambda tr(eps) I + 2 mu eps, eps = sym(H), for a general small H; the strain field
  // is Green-Lagrange's, which differs from eps by H^T H / 2.
  const double mu = 3.0e5, lambda = 7.0e5;
  const auto linear = make_material_law("linear_elastic", {{"mu", mu}, {"lambda", lambda}});
  const Mat3 H = 1e-4 * (Mat3() << 2.0, 0.5, -1.0, 0.3, -0.8, 1.0, 0.2, 0.4, -0.6).finished();
  const Mat3 eps = 0.5 * (H + H.transpose());
  const Mat3 sigma = lambda * eps.trace() * Mat3::Identity() + 2 * mu * eps;
  for (int order : {1, 2}) {
    const std::vector<double> X = mapped_tet(order, order == 2 ? 0.3 : 0.0);
    const ElementFields f =
        tet_fields(order, X.data(), homogeneous_displacement(X, H).data(), *linear);
    EXPECT_LT(largest_difference(f.stress, sigma), 1e-12 * sigma.norm()) << "order " << order;
    EXPECT_LT(largest_difference(f.strain, eps + 0.5 * H.transpose() * H), 1e-19);
    // Principal stresses: those of the symmetric sigma, by an independent route (its
    // invariants: their sum is the trace, their product the determinant).
    const auto ps = principal_values(f.stress);
    EXPECT_GE(ps[0], ps[1]);
    EXPECT_GE(ps[1], ps[2]);
    EXPECT_NEAR(ps[0] + ps[1] + ps[2], sigma.trace(), 1e-12 * sigma.norm());
    EXPECT_NEAR(ps[0] * ps[1] * ps[2], sigma.determinant(), 1e-10 * std::pow(sigma.norm(), 3));
  }
}

}  // namespace
}  // namespace hs
