// The Yeoh law beyond the checks every law gets (test_materials.cpp: P and dP/dF against
// finite differences, the small-strain limit, objectivity, principal stretches): its
// Mooney-Rivlin limit, closed forms of stretches along the axes, where a fit softens, its deck
// keys and their printing.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "common/error.hpp"
#include "material_fixtures.hpp"
#include "materials/registry.hpp"

namespace hs {
namespace {
namespace test_yeoh {

using namespace material_fixtures;

// C2 = C3 = 0 leaves C1 (I1b - 3) + kappa/2 (ln J)^2: Mooney-Rivlin with c1 = C1, c2 = 0 on the
// same constants. The two compute J^-2/3 differently (expm1 here, exp there): equal to rounding.
TEST(Yeoh, WithoutC2AndC3IsMooneyRivlinOnTheFirstInvariant) {
  const ElasticConstants c = elastic_constants_from_lame(kMu, kLambda);
  const YeohLaw yeoh(c, 0.0, 0.0);
  const MooneyRivlinLaw mooney(c, kMu / 2, 0.0);
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    const Mat3 F = random_F(rng, 0.3);
    const StressResult y = stress(yeoh, F), m = stress(mooney, F);
    EXPECT_LT(relative_error(y.P, m.P), 1e-13) << F;
    EXPECT_LT(relative_error(y.A, m.A), 1e-13) << F;
    EXPECT_NEAR(y.psi, m.psi, 1e-13 * std::abs(m.psi));
  }
}

// dpsi/dI1b at x = I1b - 3 for the fixture's law (C1 = mu / 2, kC2, kC3).
double dW(double x) { return kMu / 2 + 2 * kC2 * x + 3 * kC3 * x * x; }

// F = diag(l, t, t): J = l t^2, I1 = l^2 + 2 t^2, g = J^-2/3, w = dW(g I1 - 3);
// P = w g (2 F - 2/3 I1 F^-T) + kappa ln J F^-T gives
//   P11 = w g (2 l - 2/3 I1 / l) + kappa ln J / l,  P22 = w g (2 t - 2/3 I1 / t) + kappa ln J / t.
Eigen::Vector2d axial_stresses(double l, double t) {
  const double J = l * t * t, I1 = l * l + 2 * t * t, g = std::pow(J, -2.0 / 3.0);
  const double w = dW(g * I1 - 3), kappa = kLambda + 2 * kMu / 3;
  return {w * g * (2 * l - 2.0 / 3.0 * I1 / l) + kappa * std::log(J) / l,
          w * g * (2 * t - 2.0 / 3.0 * I1 / t) + kappa * std::log(J) / t};
}

// Uniaxial stress: the lateral stretch t with P22 = 0 (bisection on the closed form), then the
// law's P at diag(l, t, t) against the closed form's P11, and its lateral stress against zero.
// l = 3 reaches I1b - 3 ~ 6, where the C3 term dominates.
TEST(Yeoh, UniaxialStretchMatchesTheClosedForm) {
  for (double l : {0.7, 1.3, 2.2, 3.0}) {
    double lo = 0.5, hi = 1.5;  // P22 changes sign in between for these l
    ASSERT_LT(axial_stresses(l, lo)(1), 0) << "l = " << l;
    ASSERT_GT(axial_stresses(l, hi)(1), 0) << "l = " << l;
    for (int it = 0; it < 200; ++it) {
      const double mid = (lo + hi) / 2;
      (axial_stresses(l, mid)(1) > 0 ? hi : lo) = mid;
    }
    const double t = (lo + hi) / 2;
    const StressResult s = stress(law("yeoh"), Mat3(Eigen::Vector3d(l, t, t).asDiagonal()));
    const double P11 = axial_stresses(l, t)(0);
    EXPECT_NEAR(s.P(0, 0), P11, 1e-12 * std::abs(P11)) << "l = " << l;
    EXPECT_NEAR(s.P(1, 1), 0.0, 1e-12 * std::abs(P11)) << "l = " << l;
    EXPECT_NEAR(s.P(2, 2), 0.0, 1e-12 * std::abs(P11)) << "l = " << l;
    EXPECT_LT((s.P - Mat3(s.P.diagonal().asDiagonal())).norm(), 1e-14 * std::abs(P11));
  }
}

// At J = 1 (F = diag(l, 1/sqrt l, 1/sqrt l)) the Cauchy stress is 2 w dev(B): its principal
// difference is the textbook incompressible Yeoh law
//   sigma11 - sigma22 = 2 (l^2 - 1/l) dW/dI1,  dW/dI1 = C1 + 2 C2 (I1 - 3) + 3 C3 (I1 - 3)^2,
// with I1 = l^2 + 2/l.
TEST(Yeoh, IsochoricStretchGivesTheIncompressibleYeohStress) {
  for (double l : {0.5, 1.1, 2.0, 3.4}) {
    const double t = 1 / std::sqrt(l);
    const Mat3 F = Eigen::Vector3d(l, t, t).asDiagonal();
    const Mat3 sigma = cauchy_stress(law("yeoh"), F);
    const double I1 = l * l + 2 / l, w = dW(I1 - 3);
    const double expected = 2 * (l * l - 1 / l) * w;
    EXPECT_NEAR(sigma(0, 0) - sigma(1, 1), expected, 1e-12 * std::abs(expected)) << "l = " << l;
    // sigma22 = 2 w (t^2 - I1/3): the isochoric law has no pressure of its own at J = 1.
    EXPECT_NEAR(sigma(1, 1), 2 * w * (1 / l - I1 / 3), 1e-12 * std::abs(expected)) << "l = " << l;
  }
}

// Where dpsi/dI1b = C1 + 2 C2 x + 3 C3 x^2 first reaches 0 for x > 0.
TEST(Yeoh, SofteningOnsetIsTheFirstZeroOfTheShearResponse) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(yeoh_softening_onset(1.0, 0.0, 0.0), inf);
  EXPECT_EQ(yeoh_softening_onset(1.0, 0.1, 0.01), inf);
  EXPECT_EQ(yeoh_softening_onset(kMu / 2, kC2, kC3), inf);  // C2^2 < 3 C1 C3: no real root
  EXPECT_EQ(yeoh_softening_onset(1.0, -0.25, 0.0), 2.0);    // 1 - 0.5 x
  // 3 C3 x^2 + 2 C2 x + C1 = 3 (x - 1)(x - 3) = 3 x^2 - 12 x + 9: the first root, 1.
  EXPECT_NEAR(yeoh_softening_onset(9.0, -6.0, 1.0), 1.0, 1e-15);
  // C3 < 0: one positive root, -(x - 2)(3 x + 1) = -3 x^2 + 5 x + 2.
  EXPECT_NEAR(yeoh_softening_onset(2.0, 2.5, -1.0), 2.0, 1e-15);
  // A fit with a tiny negative C3 (C1 = 12.7e3, C2 = 423, C3 = -1.46 Pa): the root near 207,
  // where the shear response vanishes to rounding.
  const double x = yeoh_softening_onset(12.7e3, 423, -1.46);
  EXPECT_NEAR(12.7e3 + 2 * 423 * x - 3 * 1.46 * x * x, 0.0, 1e-9 * 12.7e3);
  EXPECT_NEAR(x, 207.1, 0.1);
}

std::string error_of(const std::map<std::string, double>& parameters) {
  try {
    make_material_law("yeoh", parameters);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(Yeoh, RegistryReadsAndChecksItsKeys) {
  const auto made = make_material_law("yeoh", {{"C1", 1.1e5}, {"C2", 2e4}, {"nu", 0.25}});
  const auto& yeoh = dynamic_cast<const YeohLaw&>(*made);
  EXPECT_EQ(made->name(), "yeoh");
  EXPECT_EQ(yeoh.C1(), 1.1e5);
  EXPECT_EQ(yeoh.C2(), 2e4);
  EXPECT_EQ(yeoh.C3(), 0.0);  // the default
  // mu = 2 C1, nu as given; E = 2 mu (1 + nu), lambda = 2 mu nu / (1 - 2 nu), exact for nu = 1/4.
  EXPECT_EQ(made->elastic_constants().mu, 2.2e5);
  EXPECT_EQ(made->elastic_constants().nu, 0.25);
  EXPECT_EQ(made->elastic_constants().E, 5.5e5);
  EXPECT_EQ(made->elastic_constants().lambda, 2.2e5);
  EXPECT_EQ(made->derived_values(), "mu = 220000, lambda = 220000, E = 550000");
  EXPECT_NE(make_material_law("yeoh", {{"C1", 1}, {"C2", -0.25}, {"nu", 0.3}})
                ->derived_values()
                .find("; dpsi/dI1b < 0 past I1b - 3 = 2 (the fit softens there)"),
            std::string::npos);

  EXPECT_NE(error_of({{"nu", 0.45}}).find("material.C1: required key missing"), std::string::npos);
  EXPECT_NE(error_of({{"C1", 0}, {"nu", 0.45}})
                .find("material.C1: must be > 0 (the small-strain shear modulus is 2 C1), got 0"),
            std::string::npos);
  EXPECT_NE(error_of({{"C1", 1e5}}).find("material.nu: required key missing"), std::string::npos);
  EXPECT_NE(error_of({{"C1", 1e5}, {"nu", 0.6}})
                .find("material.nu: must lie in (-1, 0.5] (0.5: incompressible), got 0.6"),
            std::string::npos);
  EXPECT_NE(error_of({{"C1", 1e305}, {"nu", 0.499999}}).find("material.C1: gives E = "),
            std::string::npos);
  // C2, C3 of either sign are taken (published fits have both); only C1 sets the small-strain
  // tangent.
  EXPECT_EQ(error_of({{"C1", 1e5}, {"C2", -3e4}, {"C3", -1e3}, {"nu", 0.45}}), "no error");
  // The elastic constants are not its keys: mu = 2 C1 and nu set them. The laws that read E are
  // the registry's (every other law, today).
  const std::vector<std::string> reading_E = material_laws_reading("E");
  EXPECT_EQ(std::count(reading_E.begin(), reading_E.end(), "yeoh"), 0);
  EXPECT_EQ(reading_E.size() + 1, material_law_names().size());
  EXPECT_NE(error_of({{"C1", 1e5}, {"nu", 0.45}, {"E", 1e6}})
                .find("material.E: only used by models " + join(reading_E)),
            std::string::npos)
      << error_of({{"C1", 1e5}, {"nu", 0.45}, {"E", 1e6}});
  EXPECT_NE(
      error_of({{"C1", 1e5}, {"nu", 0.45}, {"Jm", 5}}).find("material.Jm: only used by model gent"),
      std::string::npos);
}

// The printed map (the resolved deck) reads back as the same law, bit for bit.
TEST(Yeoh, PrintedKeysReadBackTheSameLaw) {
  const auto made =
      make_material_law("yeoh", {{"C1", 0.11e6}, {"C2", 0.02e6}, {"C3", -1.46}, {"nu", 0.49}});
  YAML::Emitter out;
  out << YAML::BeginMap;
  print_material_law(out, *made);
  out << YAML::EndMap;
  std::map<std::string, double> printed;
  for (const auto& item : YAML::Load(out.c_str()))
    printed[item.first.Scalar()] = item.second.as<double>();
  EXPECT_EQ(printed.size(), 4u) << out.c_str();
  const auto read_back = make_material_law("yeoh", printed);
  const auto& back = dynamic_cast<const YeohLaw&>(*read_back);
  EXPECT_EQ(back.C1(), 0.11e6);
  EXPECT_EQ(back.C2(), 0.02e6);
  EXPECT_EQ(back.C3(), -1.46);
  EXPECT_EQ(back.elastic_constants().nu, 0.49);
  EXPECT_EQ(back.elastic_constants().lambda, made->elastic_constants().lambda);
}

}  // namespace test_yeoh
}  // namespace
}  // namespace hs
