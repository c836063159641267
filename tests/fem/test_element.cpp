// Element internal force and tangent: against finite differences of the element energy and
// of the force, for every material and both orders on a distorted (P2: curved) element;
// rigid-body invariance; the rank of the linear-elastic stiffness; inverted elements.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "../materials/material_fixtures.hpp"
#include "common/error.hpp"
#include "element_fixtures.hpp"
#include "fem/element.hpp"
#include "materials/registry.hpp"
#include "materials/volumetric_term.hpp"

namespace hs {
namespace {

using namespace testing_fixtures;

// Every law of the registry, with mu = 3, lambda = 7 (tests/materials/material_fixtures.hpp).
const MaterialLaw& parameters(const std::string& model) { return material_fixtures::law(model); }

// The displacement element and the F-bar element (fbar_element.cpp) share every check.
struct Case {
  std::string model;
  int order;
  bool fbar;
};

std::vector<Case> all_cases() {
  std::vector<Case> cases;
  for (bool fbar : {false, true})
    for (int order : {1, 2})
      for (const std::string& model : material_fixtures::all_law_names())
        cases.push_back({model, order, fbar});
  return cases;
}

void PrintTo(const Case& c, std::ostream* os) {
  *os << c.model << " P" << c.order << (c.fbar ? " F-bar" : "");
}

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  return info.param.model + "_P" + std::to_string(info.param.order) +
         (info.param.fbar ? "_fbar" : "");
}

ElementOutput element_force(bool fbar, int order, const std::vector<double>& X,
                            const std::vector<double>& u, const MaterialLaw& m, double* r,
                            double* K) {
  return fbar ? tet_internal_force_fbar(order, X.data(), u.data(), m, r, K)
              : tet_internal_force(order, X.data(), u.data(), m, r, K);
}

class ElementCase : public ::testing::TestWithParam<Case> {
 protected:
  int order() const { return GetParam().order; }
  int n() const { return 3 * (order() == 1 ? 4 : 10); }
  const MaterialLaw& material() const { return parameters(GetParam().model); }
  ElementOutput force(const std::vector<double>& X, const std::vector<double>& u, double* r,
                      double* K, const MaterialLaw* m = nullptr) const {
    return element_force(GetParam().fbar, order(), X, u, m ? *m : material(), r, K);
  }
};

double max_abs(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

TEST_P(ElementCase, ForceIsTheDerivativeOfTheEnergy) {
  const std::vector<double> X = distorted_tet(order());
  const std::vector<double> u = random_vector(n(), 0.15, 11);
  std::vector<double> r(n()), scratch(n());
  ASSERT_TRUE(force(X, u, r.data(), nullptr).valid);
  const double h = 1e-6;
  std::vector<double> fd(n());
  for (int d = 0; d < n(); ++d) {
    std::vector<double> up = u, um = u;
    up[d] += h;
    um[d] -= h;
    const double ep = force(X, up, scratch.data(), nullptr).energy;
    const double em = force(X, um, scratch.data(), nullptr).energy;
    fd[d] = (ep - em) / (2 * h);
  }
  for (int d = 0; d < n(); ++d) EXPECT_NEAR(r[d], fd[d], 1e-7 * max_abs(r)) << "dof " << d;
}

TEST_P(ElementCase, TangentIsTheDerivativeOfTheForce) {
  const std::vector<double> X = distorted_tet(order());
  const std::vector<double> u = random_vector(n(), 0.15, 12);
  std::vector<double> r(n()), K(n() * n()), rp(n()), rm(n());
  force(X, u, r.data(), K.data());
  const double h = 1e-6;
  double worst = 0;
  for (int d = 0; d < n(); ++d) {
    std::vector<double> up = u, um = u;
    up[d] += h;
    um[d] -= h;
    force(X, up, rp.data(), nullptr);
    force(X, um, rm.data(), nullptr);
    for (int i = 0; i < n(); ++i)
      worst = std::max(worst, std::abs(K[i * n() + d] - (rp[i] - rm[i]) / (2 * h)));
  }
  EXPECT_LT(worst, 1e-7 * max_abs(K));
}

TEST_P(ElementCase, ForceWithTangentEqualsForceAlone) {
  const std::vector<double> X = distorted_tet(order());
  const std::vector<double> u = random_vector(n(), 0.15, 13);
  std::vector<double> r1(n()), r2(n()), K(n() * n());
  const ElementOutput a = force(X, u, r1.data(), nullptr);
  const ElementOutput b = force(X, u, r2.data(), K.data());
  EXPECT_EQ(r1, r2);
  EXPECT_EQ(a.energy, b.energy);
}

TEST_P(ElementCase, RigidTranslationGivesNoForce) {
  const std::vector<double> X = distorted_tet(order());
  std::vector<double> u(n()), r(n());
  for (int a = 0; a < n() / 3; ++a) u[3 * a] = 0.3, u[3 * a + 1] = -1.2, u[3 * a + 2] = 0.7;
  const ElementOutput out = force(X, u, r.data(), nullptr);
  EXPECT_LT(max_abs(r), 1e-13);
  EXPECT_NEAR(out.energy, 0.0, 1e-14);
}

TEST_P(ElementCase, TangentAtRestIsTheLinearElasticStiffness) {
  const std::vector<double> X = distorted_tet(order());
  const std::vector<double> u(n(), 0.0);
  std::vector<double> r(n()), K(n() * n()), K_linear(n() * n());
  force(X, u, r.data(), K.data());
  force(X, u, r.data(), K_linear.data(), &parameters("linear_elastic"));
  for (int i = 0; i < n() * n(); ++i) EXPECT_NEAR(K[i], K_linear[i], 1e-13 * max_abs(K_linear));
}

INSTANTIATE_TEST_SUITE_P(Elements, ElementCase, ::testing::ValuesIn(all_cases()), case_name);

class FiniteStrainElement : public ElementCase {};

TEST_P(FiniteStrainElement, RigidRotationGivesNoForce) {
  const std::vector<double> X = distorted_tet(order());
  const Eigen::Matrix3d Q =
      Eigen::AngleAxisd(1.1, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  std::vector<double> u(n()), r(n());
  for (int a = 0; a < n() / 3; ++a) {
    const Eigen::Vector3d x(X[3 * a], X[3 * a + 1], X[3 * a + 2]);
    const Eigen::Vector3d d = Q * x - x + Eigen::Vector3d(0.2, 0.1, -0.3);
    for (int i = 0; i < 3; ++i) u[3 * a + i] = d(i);
  }
  const ElementOutput out = force(X, u, r.data(), nullptr);
  EXPECT_LT(max_abs(r), 1e-12);
  EXPECT_NEAR(out.energy, 0.0, 1e-13);
}

TEST_P(FiniteStrainElement, InvertedElementIsReported) {
  std::vector<double> X = distorted_tet(order());
  std::vector<double> u(n(), 0.0), r(n());
  // Push vertex 3 through the opposite face (and the P2 edge nodes with it).
  const double dz = -2.0;
  u[3 * 3 + 2] = dz;
  if (order() == 2)
    for (int node : {7, 8, 9}) u[3 * node + 2] = dz / 2;
  EXPECT_FALSE(force(X, u, r.data(), nullptr).valid);
}

// On a P1 element J = Jbar: the F-bar element is the displacement element.
TEST(FbarElement, OnP1IsTheDisplacementElement) {
  const std::vector<double> X = distorted_tet(1);
  const std::vector<double> u = random_vector(12, 0.15, 21);
  for (const std::string& model : material_fixtures::all_law_names()) {
    const MaterialLaw& m = parameters(model);
    std::vector<double> r(12), K(144), r1(12), K1(144);
    const ElementOutput a = tet_internal_force(1, X.data(), u.data(), m, r.data(), K.data());
    const ElementOutput b = tet_internal_force_fbar(1, X.data(), u.data(), m, r1.data(), K1.data());
    EXPECT_NEAR(a.energy, b.energy, 1e-13 * std::abs(a.energy)) << model;
    for (int k = 0; k < 12; ++k) EXPECT_NEAR(r[k], r1[k], 1e-12 * max_abs(r)) << model;
    for (int k = 0; k < 144; ++k) EXPECT_NEAR(K[k], K1[k], 1e-12 * max_abs(K)) << model;
  }
}

// Newton's own pressure in the F-bar element's tangent (element.hpp, FbarNewtonPressure), for
// every finite-strain law with the volumetric term, at nu = 0.4999 on the curved P2 element:
// with the exact pressure the split law gives the plain element's energy, force and tangent;
// with the pressure linearised from a point u0 the force stays exact and the tangent differs
// from the exact one by O(|u - u0|^2) (a quarter when the distance halves).
TEST(FbarElement, NewtonsPressureTangentIsExactAtItsPointAndSecondOrderAway) {
  const std::vector<double> X = distorted_tet(2);
  const std::vector<double> u0 = random_vector(30, 0.1, 5);
  const std::vector<double> du = random_vector(30, 0.02, 6);
  int laws = 0;
  for (const std::string& model : material_fixtures::all_law_names()) {
    const auto law = material_fixtures::make_law(model, elastic_constants_from_E_nu(1.0, 0.4999));
    if (!law->has_volumetric_term() || law->small_strain()) continue;
    ++laws;
    const WithoutVolumetricTerm rest(law);
    FbarNewtonPressure p;
    p.rest = &rest;
    p.k = law->volumetric_modulus();
    std::vector<double> r(30), K(900), r1(30), K1(900);
    const ElementOutput a =
        tet_internal_force_fbar(2, X.data(), u0.data(), *law, r.data(), K.data());
    const ElementOutput b =
        tet_internal_force_fbar(2, X.data(), u0.data(), p, r1.data(), K1.data());
    EXPECT_NEAR(a.energy, b.energy, 1e-10 * std::abs(a.energy)) << model;
    for (int k = 0; k < 30; ++k) EXPECT_NEAR(r[k], r1[k], 1e-9 * max_abs(r)) << model;
    for (int k = 0; k < 900; ++k) EXPECT_NEAR(K[k], K1[k], 1e-9 * max_abs(K)) << model;
    const double ln_Jbar0 = p.ln_Jbar;
    const std::vector<double> g0(p.g, p.g + 30);
    double gap[2];
    for (int halving = 0; halving < 2; ++halving) {
      std::vector<double> u = u0;
      double g_du = 0;
      for (int k = 0; k < 30; ++k) {
        u[k] += du[k] / (1 << halving);
        g_du += g0[k] * du[k] / (1 << halving);
      }
      p.exact = false;
      p.q = p.k * (ln_Jbar0 + g_du);
      tet_internal_force_fbar(2, X.data(), u.data(), p, r1.data(), K1.data());
      tet_internal_force_fbar(2, X.data(), u.data(), *law, r.data(), K.data());
      for (int k = 0; k < 30; ++k) EXPECT_NEAR(r[k], r1[k], 1e-9 * max_abs(r)) << model;
      std::vector<double> diff(900);
      for (int k = 0; k < 900; ++k) diff[k] = K1[k] - K[k];
      gap[halving] = max_abs(diff) / max_abs(K);
    }
    EXPECT_GT(gap[0], 1e-8) << model;  // the pressures differ: the tangents do
    EXPECT_NEAR(gap[1] / gap[0], 0.25, 0.05) << model;
  }
  EXPECT_GE(laws, 4);
}

// The volume ratio the multipliers' raises read (solvers/problem_multipliers.cpp): det F of a
// homogeneous deformation, and on a curved element with any displacement the kernel's own.
TEST(FbarElement, VolumeRatioIsDetFOfAHomogeneousDeformationAndTheKernels) {
  const std::vector<double> straight = distorted_tet(2, 0.0);
  const Eigen::Matrix3d H = Eigen::Map<const Eigen::Matrix3d>(random_vector(9, 0.2, 3).data());
  std::vector<double> affine(30);
  for (int a = 0; a < 10; ++a) {
    const Eigen::Vector3d moved = H * Eigen::Map<const Eigen::Vector3d>(&straight[3 * a]);
    for (int d = 0; d < 3; ++d) affine[3 * a + d] = moved(d);
  }
  EXPECT_NEAR(1 + tet_volume_ratio_minus_one_fbar(2, straight.data(), affine.data()),
              (Eigen::Matrix3d::Identity() + H).determinant(), 1e-14);

  const std::vector<double> X = distorted_tet(2);
  const std::vector<double> u = random_vector(30, 0.1, 7);
  const auto law =
      material_fixtures::make_law("neo_hookean", elastic_constants_from_E_nu(1.0, 0.5));
  const WithoutVolumetricTerm rest(law);
  FbarNewtonPressure p;
  p.rest = &rest;
  p.k = law->volumetric_modulus();
  std::vector<double> r(30);
  tet_internal_force_fbar(2, X.data(), u.data(), p, r.data(), nullptr);
  EXPECT_GT(std::abs(p.ln_Jbar), 1e-3);  // the displacement changes the volume
  EXPECT_EQ(std::log1p(tet_volume_ratio_minus_one_fbar(2, X.data(), u.data())), p.ln_Jbar);
}

// An exactly incompressible element's volume multiplier (nu = 0.5) adds V lambda ln Jbar to the
// energy: its force is that energy's derivative and its tangent the force's, for every
// finite-strain law with the term.
TEST(FbarElement, VolumeMultipliersTermHasItsEnergysDerivatives) {
  const std::vector<double> X = distorted_tet(2);
  const std::vector<double> u = random_vector(30, 0.1, 7);
  const std::vector<double> v = random_vector(30, 1.0, 8);
  const double V = tet_volume(2, X.data()), eps = 1e-6;
  int laws = 0;
  for (const std::string& model : material_fixtures::all_law_names()) {
    const auto law = material_fixtures::make_law(model, elastic_constants_from_E_nu(1.0, 0.5));
    if (!law->has_volumetric_term() || law->small_strain()) continue;
    ++laws;
    const WithoutVolumetricTerm rest(law);
    FbarNewtonPressure p;
    p.rest = &rest;
    p.k = law->volumetric_modulus();
    std::vector<double> r(30), K(900), rp(30), rm(30);
    const double plain =
        tet_internal_force_fbar(2, X.data(), u.data(), p, r.data(), nullptr).energy;
    p.lambda = 0.3;
    const ElementOutput out = tet_internal_force_fbar(2, X.data(), u.data(), p, r.data(), K.data());
    // V ln Jbar on the element's stiffness rule (not exact on a curved element: 4e-5 here).
    EXPECT_NEAR(out.energy - plain, V * 0.3 * p.ln_Jbar, 1e-3 * std::abs(V * 0.3 * p.ln_Jbar))
        << model;
    std::vector<double> up = u, um = u;
    for (int k = 0; k < 30; ++k) {
      up[k] += eps * v[k];
      um[k] -= eps * v[k];
    }
    const double Ep = tet_internal_force_fbar(2, X.data(), up.data(), p, rp.data(), nullptr).energy;
    const double Em = tet_internal_force_fbar(2, X.data(), um.data(), p, rm.data(), nullptr).energy;
    double slope = 0;
    for (int k = 0; k < 30; ++k) slope += r[k] * v[k];
    EXPECT_NEAR((Ep - Em) / (2 * eps), slope, 1e-6 * max_abs(r) * max_abs(v)) << model;
    std::vector<double> Kv(30, 0.0), difference(30);
    for (int i = 0; i < 30; ++i)
      for (int j = 0; j < 30; ++j) Kv[i] += K[30 * i + j] * v[j];
    for (int k = 0; k < 30; ++k) difference[k] = (rp[k] - rm[k]) / (2 * eps) - Kv[k];
    EXPECT_LT(max_abs(difference), 1e-6 * max_abs(Kv)) << model;
  }
  EXPECT_GE(laws, 4);
}

// The assembly's P1 path reads the reference geometry kept per element: it must give the
// generic routine's force and tangent for every law, at a large strain.
TEST(P1Geometry, KeptGeometryGivesTheSameForceAndTangent) {
  const std::vector<double> X = distorted_tet(1);
  std::vector<double> u(12);
  for (int k = 0; k < 12; ++k) u[k] = 0.05 * std::sin(1.7 * k + 0.3);
  const P1Geometry g = tet_p1_geometry(X.data());
  for (const std::string& model : material_fixtures::all_law_names()) {
    const MaterialLaw& m = parameters(model);
    std::vector<double> r(12), K(144), r1(12), K1(144);
    const ElementOutput a = tet_internal_force(1, X.data(), u.data(), m, r.data(), K.data());
    const ElementOutput b = tet_internal_force_p1(g, u.data(), m, r1.data(), K1.data());
    EXPECT_NEAR(a.energy, b.energy, 1e-14 * std::abs(a.energy)) << model;
    for (int k = 0; k < 12; ++k) EXPECT_NEAR(r[k], r1[k], 1e-13 * max_abs(r));
    for (int k = 0; k < 144; ++k) EXPECT_NEAR(K[k], K1[k], 1e-13 * max_abs(K));
  }
  EXPECT_NEAR(g.volume, tet_volume(1, X.data()), 1e-15);
}

// The nodal-pressure element's volume of a P1 element: the change against the volume of the
// moved vertices, its gradient and Hessian against central differences (v is cubic in u, so
// the differences are exact up to round-off).
TEST(P1Volume, ChangeGradientAndHessianAreTheVolumesDerivatives) {
  const std::vector<double> X = distorted_tet(1);
  const P1Geometry g = tet_p1_geometry(X.data());
  std::vector<double> u(12);
  for (int k = 0; k < 12; ++k) u[k] = 0.2 * std::sin(1.3 * k + 0.7);
  auto volume = [&](const std::vector<double>& d) {
    std::vector<double> x(12);
    for (int k = 0; k < 12; ++k) x[k] = X[k] + d[k];
    const Eigen::Vector3d a(x[3] - x[0], x[4] - x[1], x[5] - x[2]);
    const Eigen::Vector3d b(x[6] - x[0], x[7] - x[1], x[8] - x[2]);
    const Eigen::Vector3d c(x[9] - x[0], x[10] - x[1], x[11] - x[2]);
    return a.dot(b.cross(c)) / 6;
  };
  std::vector<double> grad(12), hess(144), gp(12), gm(12);
  const double change = p1_volume_change(g, u.data(), grad.data(), hess.data());
  EXPECT_NEAR(change, volume(u) - g.volume, 1e-14 * g.volume);
  const double h = 1e-5;
  for (int k = 0; k < 12; ++k) {
    std::vector<double> up = u, um = u;
    up[k] += h;
    um[k] -= h;
    EXPECT_NEAR(grad[k], (volume(up) - volume(um)) / (2 * h), 1e-8 * max_abs(grad)) << k;
    p1_volume_change(g, up.data(), gp.data(), nullptr);
    p1_volume_change(g, um.data(), gm.data(), nullptr);
    for (int i = 0; i < 12; ++i)
      EXPECT_NEAR(hess[12 * i + k], (gp[i] - gm[i]) / (2 * h), 1e-8 * max_abs(hess))
          << i << " " << k;
  }
  // A small change keeps its digits: v - V is not a difference of two volumes.
  std::vector<double> tiny(12);
  for (int k = 0; k < 12; ++k) tiny[k] = 1e-12 * u[k];
  const double small = p1_volume_change(g, tiny.data(), grad.data(), nullptr);
  double linear = 0;
  for (int k = 0; k < 12; ++k) linear += grad[k] * tiny[k];
  EXPECT_NEAR(small, linear, 1e-9 * std::abs(linear));
  // Linearised (a small-strain law's): V tr(H) and the gradient at rest, no Hessian.
  std::vector<double> grad0(12);
  p1_volume_change(g, std::vector<double>(12, 0.0).data(), grad0.data(), nullptr);
  const double lin = p1_volume_change(g, u.data(), grad.data(), hess.data(), true);
  double expected = 0;
  for (int k = 0; k < 12; ++k) {
    expected += grad0[k] * u[k];
    EXPECT_NEAR(grad[k], grad0[k], 1e-15 * max_abs(grad0));
  }
  EXPECT_NEAR(lin, expected, 1e-14 * g.volume);
  EXPECT_EQ(max_abs(hess), 0.0);
}

std::vector<Case> finite_strain_cases() {
  std::vector<Case> cases;
  for (const Case& c : all_cases())
    if (c.model != "linear_elastic") cases.push_back(c);
  return cases;
}

INSTANTIATE_TEST_SUITE_P(Elements, FiniteStrainElement, ::testing::ValuesIn(finite_strain_cases()),
                         case_name);

class Order : public ::testing::TestWithParam<int> {};

// Eigenvalues of the linear-elastic stiffness at rest (checked symmetric) of the displacement
// or the F-bar element, for the Lame constants (mu, lambda), on the distorted element with its
// P2 edge nodes moved by up to `curvature`.
Eigen::VectorXd stiffness_eigenvalues(int order, bool fbar, double mu, double lambda,
                                      double curvature = 0.06) {
  const int n = 3 * (order == 1 ? 4 : 10);
  const std::vector<double> X = distorted_tet(order, curvature);
  const std::vector<double> u(n, 0.0);
  std::vector<double> r(n), K(n * n);
  const auto law =
      material_fixtures::make_law("linear_elastic", elastic_constants_from_lame(mu, lambda));
  element_force(fbar, order, X, u, *law, r.data(), K.data());
  const Eigen::MatrixXd Km = Eigen::Map<const Eigen::MatrixXd>(K.data(), n, n);
  EXPECT_LT((Km - Km.transpose()).norm(), 1e-14 * Km.norm());
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Km).eigenvalues();
}

// Six rigid modes; the F-bar P2 element three more, the special conformal fields (zero
// deviatoric strain, zero mean dilatation; exact zeros on a straight element, fbar_element.cpp).
TEST_P(Order, LinearElasticStiffnessHasExactlyItsZeroEnergyModes) {
  const int n = 3 * (GetParam() == 1 ? 4 : 10);
  for (bool fbar : {false, true}) {
    const Eigen::VectorXd ev = stiffness_eigenvalues(GetParam(), fbar, material_fixtures::kMu,
                                                     material_fixtures::kLambda, 0.0);
    const int zeros = fbar && GetParam() == 2 ? 9 : 6;
    const double largest = ev(n - 1);
    for (int i = 0; i < zeros; ++i)
      EXPECT_LT(std::abs(ev(i)), 1e-12 * largest) << "eigenvalue " << i << (fbar ? " F-bar" : "");
    EXPECT_GT(ev(zeros), 1e-3 * largest) << (fbar ? "F-bar" : "");
  }
}

// Locking, counted: with lambda = 1e8 mu the modes whose stiffness grows with lambda are the
// element's volumetric constraints. The displacement P2 element has one per quadrature point
// (4), the F-bar element one (its volume); on P1 both have one.
TEST_P(Order, FbarLeavesOneVolumetricConstraintPerElement) {
  const double mu = 1.0, lambda = 1e8;
  for (bool fbar : {false, true}) {
    const Eigen::VectorXd ev = stiffness_eigenvalues(GetParam(), fbar, mu, lambda);
    const long stiff = (ev.array() > 1e3 * mu).count();
    EXPECT_EQ(stiff, GetParam() == 2 && !fbar ? 4 : 1) << (fbar ? "F-bar" : "displacement");
  }
}

TEST_P(Order, InvertedReferenceElementIsAnInputError) {
  const int order = GetParam(), n = 3 * (order == 1 ? 4 : 10);
  std::vector<double> X = distorted_tet(order);
  std::swap_ranges(X.begin() + 3, X.begin() + 6, X.begin() + 6);  // swap vertices 1 and 2
  if (order == 2) {  // keep the edge nodes on the swapped edges: (0,1) <-> (2,0), (3,2) <-> (3,1)
    std::swap_ranges(X.begin() + 12, X.begin() + 15, X.begin() + 18);
    std::swap_ranges(X.begin() + 24, X.begin() + 27, X.begin() + 27);
  }
  const std::vector<double> u(n, 0.0);
  std::vector<double> r(n);
  EXPECT_THROW(
      tet_internal_force(order, X.data(), u.data(), parameters("neo_hookean"), r.data(), nullptr),
      InputError);
  EXPECT_THROW(tet_volume(order, X.data()), InputError);
}

// The step's inversion check reads positions only; it must agree with det F of tet_fields
// (a different computation: F from the reference gradients) as a vertex is pushed through
// the opposite face, and refuse a non-finite displacement.
TEST_P(Order, OrientationCheckAgreesWithDetF) {
  const int order = GetParam(), n = 3 * (order == 1 ? 4 : 10);
  const std::vector<double> X = distorted_tet(order);
  const MaterialLaw& m = parameters("neo_hookean");
  int inverted = 0;
  for (double dz = 0.5; dz > -3.0; dz -= 0.0625) {
    std::vector<double> u(n, 0.0);
    u[3 * 3 + 2] = dz;
    if (order == 2)
      for (int node : {7, 8, 9}) u[3 * node + 2] = dz / 2;
    const double J = tet_fields(order, X.data(), u.data(), m).J;
    if (std::abs(J) < 1e-12) continue;  // on the face: either answer is round-off
    EXPECT_EQ(tet_orientation_preserved(order, X.data(), u.data()), J > 0) << "dz " << dz;
    inverted += J < 0;
  }
  EXPECT_GT(inverted, 10);  // the sweep went through the face
  std::vector<double> u(n, 0.0);
  u[4] = std::nan("");
  EXPECT_FALSE(tet_orientation_preserved(order, X.data(), u.data()));
}

INSTANTIATE_TEST_SUITE_P(Elements, Order, ::testing::Values(1, 2));

}  // namespace
}  // namespace hs
