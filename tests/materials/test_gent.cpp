// The Gent law beyond the checks every law gets (test_materials.cpp: P and dP/dF against
// finite differences, the small-strain limit, objectivity, principal stretches): its large-Jm
// limit, closed forms of stretches along the axes, the limiting chain, its deck keys.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "common/error.hpp"
#include "material_fixtures.hpp"
#include "materials/registry.hpp"

namespace hs {
namespace {

using namespace material_fixtures;

// As Jm -> inf, -mu Jm/2 ln(1 - (I1b - 3)/Jm) -> mu/2 (I1b - 3): Mooney-Rivlin with c1 = mu/2,
// c2 = 0 and the same volumetric term kappa/2 (ln J)^2, kappa = lambda + 2 mu / 3. The
// difference is of relative order (I1b - 3)/Jm ~ 1e-9.
TEST(Gent, LargeJmIsMooneyRivlinOnTheFirstInvariant) {
  const ElasticConstants c = elastic_constants_from_lame(kMu, kLambda);
  const GentLaw gent(c, 1e9);
  const MooneyRivlinLaw mooney(c, kMu / 2, 0.0);
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    const Mat3 F = random_F(rng, 0.3);
    const StressResult g = stress(gent, F), m = stress(mooney, F);
    EXPECT_LT(relative_error(g.P, m.P), 1e-8) << F;
    EXPECT_LT(relative_error(g.A, m.A), 1e-8) << F;
    EXPECT_NEAR(g.psi, m.psi, 1e-8 * std::abs(m.psi));
  }
}

// F = diag(l, t, t): J = l t^2, I1 = l^2 + 2 t^2, g = J^-2/3, x = (g I1 - 3)/Jm and
// w = mu / (2 (1 - x)); P = w g (2 F - 2/3 I1 F^-T) + kappa ln J F^-T gives
//   P11 = w g (2 l - 2/3 I1 / l) + kappa ln J / l,  P22 = w g (2 t - 2/3 I1 / t) + kappa ln J / t.
Eigen::Vector2d axial_stresses(double l, double t) {
  const double J = l * t * t, I1 = l * l + 2 * t * t, g = std::pow(J, -2.0 / 3.0);
  const double w = kMu / (2 * (1 - (g * I1 - 3) / kJm)), kappa = kLambda + 2 * kMu / 3;
  return {w * g * (2 * l - 2.0 / 3.0 * I1 / l) + kappa * std::log(J) / l,
          w * g * (2 * t - 2.0 / 3.0 * I1 / t) + kappa * std::log(J) / t};
}

// Uniaxial stress: the lateral stretch t with P22 = 0 (bisection on the closed form), then the
// law's P at diag(l, t, t) against the closed form's P11, and its lateral stress against zero.
TEST(Gent, UniaxialStretchMatchesTheClosedForm) {
  for (double l : {0.7, 1.3, 2.2, 3.0}) {
    double lo = 0.5, hi = 1.5;  // inside the chain for these l; P22 changes sign in between
    ASSERT_LT(axial_stresses(l, lo)(1), 0) << "l = " << l;
    ASSERT_GT(axial_stresses(l, hi)(1), 0) << "l = " << l;
    for (int it = 0; it < 200; ++it) {
      const double mid = (lo + hi) / 2;
      (axial_stresses(l, mid)(1) > 0 ? hi : lo) = mid;
    }
    const double t = (lo + hi) / 2;
    const Eigen::Vector3d stretches(l, t, t);
    const StressResult s = stress(law("gent"), Mat3(stretches.asDiagonal()));
    const double P11 = axial_stresses(l, t)(0);
    EXPECT_NEAR(s.P(0, 0), P11, 1e-12 * std::abs(P11)) << "l = " << l;
    EXPECT_NEAR(s.P(1, 1), 0.0, 1e-12 * std::abs(P11)) << "l = " << l;
    EXPECT_NEAR(s.P(2, 2), 0.0, 1e-12 * std::abs(P11)) << "l = " << l;
    EXPECT_LT((s.P - Mat3(s.P.diagonal().asDiagonal())).norm(), 1e-14 * std::abs(P11));
  }
}

// At J = 1 (F = diag(l, 1/sqrt l, 1/sqrt l)) the Cauchy stress is 2 w dev(b): its principal
// difference is the textbook incompressible Gent law
//   sigma11 - sigma22 = mu (l^2 - 1/l) / (1 - (l^2 + 2/l - 3)/Jm),
// stiffening without bound as l^2 + 2/l - 3 nears Jm.
TEST(Gent, IsochoricStretchGivesTheIncompressibleGentStress) {
  for (double l : {0.5, 1.1, 2.0, 3.4}) {
    const double t = 1 / std::sqrt(l);
    const Mat3 F = Eigen::Vector3d(l, t, t).asDiagonal();
    const Mat3 sigma = cauchy_stress(law("gent"), F);
    const double x = (l * l + 2 / l - 3) / kJm;
    const double expected = kMu * (l * l - 1 / l) / (1 - x);
    EXPECT_NEAR(sigma(0, 0) - sigma(1, 1), expected, 1e-12 * std::abs(expected)) << "l = " << l;
    // sigma22 = 2 w (t^2 - I1/3): the isochoric law has no pressure of its own at J = 1.
    const double sigma22 = kMu / (1 - x) * (1 / l - (l * l + 2 / l) / 3);
    EXPECT_NEAR(sigma(1, 1), sigma22, 1e-12 * std::abs(expected)) << "l = " << l;
  }
}

// Past the limiting chain (I1b - 3 >= Jm) the point is treated as inverted, so that Newton
// cuts the step back; just inside, the energy is finite and steep.
TEST(Gent, BeyondTheLimitingChainThePointIsInverted) {
  // l^2 + 2/l - 3 at J = 1: 9.82 for l = 3.5, 10.5 for l = 3.6 (Jm = 10).
  auto isochoric = [](double l) {
    const double t = 1 / std::sqrt(l);
    return Mat3(Eigen::Vector3d(l, t, t).asDiagonal());
  };
  const StressResult inside = stress(law("gent"), isochoric(3.5));
  EXPECT_TRUE(std::isfinite(inside.psi));
  EXPECT_TRUE(inside.P.allFinite());
  EXPECT_TRUE(inside.A.allFinite());
  // At J = 1 the stress is that of Mooney-Rivlin with c1 = mu/2, c2 = 0 times 1/(1 - x), here 55.
  const double x = (3.5 * 3.5 + 2 / 3.5 - 3) / kJm;
  const MooneyRivlinLaw mooney(elastic_constants_from_lame(kMu, kLambda), kMu / 2, 0.0);
  const Mat3 P_mooney = stress(mooney, isochoric(3.5)).P;
  EXPECT_LT(relative_error(inside.P, P_mooney / (1 - x)), 1e-12);
  const StressResult outside = stress(law("gent"), isochoric(3.6));
  EXPECT_FALSE(std::isfinite(outside.psi));
  EXPECT_TRUE(outside.P.array().isNaN().all());
  EXPECT_TRUE(outside.A.array().isNaN().all());
}

std::string error_of(const std::map<std::string, double>& parameters) {
  try {
    make_material_law("gent", parameters);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(Gent, RegistryReadsAndChecksItsKeys) {
  const auto made = make_material_law("gent", {{"E", 1e6}, {"nu", 0.45}, {"Jm", 20}});
  EXPECT_EQ(made->name(), "gent");
  EXPECT_EQ(dynamic_cast<const GentLaw&>(*made).Jm(), 20);
  EXPECT_EQ(made->elastic_constants().mu, 1e6 / (2 * 1.45));
  EXPECT_NE(error_of({{"E", 1e6}, {"nu", 0.45}}).find("material.Jm: required key missing"),
            std::string::npos);
  EXPECT_NE(error_of({{"E", 1e6}, {"nu", 0.45}, {"Jm", 0}}).find("material.Jm: must be > 0"),
            std::string::npos);
  EXPECT_NE(error_of({{"E", 1e6}, {"nu", 0.45}, {"Jm", 5}, {"c1", 1}})
                .find("material.c1: only used by model mooney_rivlin"),
            std::string::npos);
  EXPECT_NE(error_of({{"Jm", 5}}).find("elastic constants missing"), std::string::npos);
}

}  // namespace
}  // namespace hs
