// Pointwise constitutive laws against finite differences, closed forms in principal
// stretches, the small-strain limit and objectivity.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <map>
#include <random>
#include <stdexcept>

#include "common/error.hpp"
#include "material_fixtures.hpp"
#include "materials/registry.hpp"

namespace hs {
namespace {

using namespace material_fixtures;

class EveryModel : public ::testing::TestWithParam<std::string> {};

TEST_P(EveryModel, StressIsTheDerivativeOfTheEnergy) {
  const MaterialLaw& m = law(GetParam());
  std::mt19937 rng(1);
  for (double amplitude : {0.01, 0.3}) {
    for (int trial = 0; trial < 20; ++trial) {
      const Mat3 F = random_F(rng, amplitude);
      const StressResult s = stress(m, F);
      EXPECT_LT(relative_error(s.P, fd_stress(m, F, 1e-5)), 1e-7)
          << m.name() << " amplitude " << amplitude << "\nF =\n"
          << F;
    }
  }
}

TEST_P(EveryModel, TangentIsTheDerivativeOfTheStress) {
  const MaterialLaw& m = law(GetParam());
  std::mt19937 rng(2);
  for (double amplitude : {0.01, 0.3}) {
    for (int trial = 0; trial < 20; ++trial) {
      const Mat3 F = random_F(rng, amplitude);
      const StressResult s = stress(m, F);
      EXPECT_LT(relative_error(s.A, fd_tangent(m, F, 1e-5)), 1e-7)
          << m.name() << " amplitude " << amplitude << "\nF =\n"
          << F;
      // All the laws derive from an energy: the tangent has the major symmetry.
      EXPECT_LT((s.A - s.A.transpose()).norm(), 1e-12 * s.A.norm());
    }
  }
}

TEST_P(EveryModel, TangentAtIdentityIsTheLinearElasticOne) {
  const MaterialLaw& m = law(GetParam());
  // lambda d_ij d_kl + mu (d_ik d_jl + d_il d_jk), written out index by index.
  Tangent reference;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l)
          reference(3 * i + j, 3 * k + l) =
              kLambda * (i == j) * (k == l) + kMu * ((i == k) * (j == l) + (i == l) * (j == k));
  EXPECT_LT(relative_error(stress(m, Mat3::Identity()).A, reference), 1e-14);
}

TEST_P(EveryModel, NoStressNoEnergyAtIdentity) {
  const StressResult s = stress(law(GetParam()), Mat3::Identity());
  EXPECT_LT(s.P.norm(), 1e-14 * kLambda);
  EXPECT_NEAR(s.psi, 0.0, 1e-14 * kLambda);
}

TEST_P(EveryModel, TinyStrainKeepsItsRelativePrecision) {
  // At |H| ~ 1e-11 every law is linear to 1e-11; computing through F = I + H would lose
  // 1e-16 / 1e-11 = 1e-5 of the stress (a residual floor of 1e-16 E for small loads).
  const MaterialLaw& m = law(GetParam());
  std::mt19937 rng(6);
  for (int trial = 0; trial < 10; ++trial) {
    const Mat3 H = 1e-11 * (random_F(rng, 1.0) - Mat3::Identity());
    const Mat3 eps = 0.5 * (H + H.transpose());
    const Mat3 linear = kLambda * eps.trace() * Mat3::Identity() + 2 * kMu * eps;
    EXPECT_LT(relative_error(stress_from_displacement_gradient(m, H, false).P, linear), 1e-9);
  }
}

TEST_P(EveryModel, ResidualOnlyCallGivesTheSameStress) {
  const MaterialLaw& m = law(GetParam());
  std::mt19937 rng(3);
  const Mat3 F = random_F(rng, 0.3);
  const StressResult full = stress(m, F), light = stress(m, F, false);
  EXPECT_EQ(full.P, light.P);
  EXPECT_EQ(full.psi, light.psi);
}

INSTANTIATE_TEST_SUITE_P(Materials, EveryModel, ::testing::ValuesIn(all_law_names()),
                         [](const auto& info) { return info.param; });

class FiniteStrainModel : public ::testing::TestWithParam<std::string> {};

TEST_P(FiniteStrainModel, IsObjective) {
  const MaterialLaw& m = law(GetParam());
  std::mt19937 rng(4);
  for (int trial = 0; trial < 20; ++trial) {
    const Mat3 F = random_F(rng, 0.4), Q = random_rotation(rng);
    const StressResult s = stress(m, F), sq = stress(m, Q * F);
    EXPECT_LT(relative_error(sq.P, Q * s.P), 1e-12);
    EXPECT_NEAR(sq.psi, s.psi, 1e-12 * std::abs(s.psi));
  }
}

// A control answer checks every element's orientation in place of its stress where the law
// says its stress is finite wherever det F > 0: at stretches of 1e-3 to 1e3, shears of 100
// and det F down to 1e-9, such a law's stress and energy are finite; Gent's says otherwise and
// has none past its chains' limit.
TEST_P(EveryModel, FiniteWhereverOrientedHoldsAtExtremeStretches) {
  const MaterialLaw& m = law(GetParam());
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> exponent(-3.0, 3.0), shear(-100.0, 100.0);
  int undefined = 0;
  for (int trial = 0; trial < 400; ++trial) {
    Mat3 F = Mat3::Identity();
    for (int i = 0; i < 3; ++i) F(i, i) = std::pow(10.0, exponent(rng));
    F(0, 1) = shear(rng);
    F(1, 2) = shear(rng) * (trial % 2);
    if (trial % 50 == 0) F = Eigen::Vector3d(1e-3, 1e-3, 1e-3).asDiagonal();  // det F 1e-9
    F = random_rotation(rng) * F;
    ASSERT_GT(F.determinant(), 0);
    const StressResult r = stress(m, F);
    const bool finite = std::isfinite(r.psi) && r.P.allFinite();
    if (m.finite_wherever_oriented()) EXPECT_TRUE(finite) << GetParam() << " at\n" << F;
    undefined += !finite;
  }
  // Gent's stretches past I1b - 3 = Jm (10 here) at most of these gradients.
  EXPECT_EQ(undefined > 0, !m.finite_wherever_oriented()) << undefined;
}

TEST_P(FiniteStrainModel, InvertedOrFlatPointHasNoFiniteEnergy) {
  const MaterialLaw& m = law(GetParam());
  const Mat3 reflected = Eigen::Vector3d(1.1, 0.9, -0.8).asDiagonal();
  const Mat3 flat = Eigen::Vector3d(1.1, 0.9, 0.0).asDiagonal();
  EXPECT_FALSE(std::isfinite(stress(m, reflected).psi));
  EXPECT_FALSE(std::isfinite(stress(m, flat).psi));
  EXPECT_FALSE(std::isfinite(stress(m, -Mat3::Identity()).psi));
}

// Energy in principal stretches on F = Q1 diag(l) Q2^T: a reference that shares no code with
// the invariant / polar forms of the laws.
double principal_energy(const std::string& model, const Eigen::Vector3d& l) {
  const double J = l.prod(), lnJ = std::log(J);
  const Eigen::Vector3d l2 = l.cwiseProduct(l);
  const double kappa = kLambda + 2 * kMu / 3;
  if (model == "corotational") {
    const Eigen::Vector3d e = l - Eigen::Vector3d::Ones();
    return kMu * e.squaredNorm() + 0.5 * kLambda * e.sum() * e.sum();
  }
  if (model == "saint_venant_kirchhoff") {
    const Eigen::Vector3d E = 0.5 * (l2 - Eigen::Vector3d::Ones());
    return kMu * E.squaredNorm() + 0.5 * kLambda * E.sum() * E.sum();
  }
  if (model == "neo_hookean")
    return 0.5 * kMu * (l2.sum() - 3) - kMu * lnJ + 0.5 * kLambda * lnJ * lnJ;
  const double I1b = std::pow(J, -2.0 / 3.0) * l2.sum();
  if (model == "mooney_rivlin") {
    const double I2b = std::pow(J, -4.0 / 3.0) * (l2(0) * l2(1) + l2(1) * l2(2) + l2(2) * l2(0));
    return 0.3 * kMu * (I1b - 3) + 0.2 * kMu * (I2b - 3) + 0.5 * kappa * lnJ * lnJ;
  }
  if (model == "gent")
    return -0.5 * kMu * kJm * std::log(1 - (I1b - 3) / kJm) + 0.5 * kappa * lnJ * lnJ;
  if (model == "yeoh") {
    const double x = I1b - 3;
    return kMu / 2 * x + kC2 * x * x + kC3 * x * x * x + 0.5 * kappa * lnJ * lnJ;
  }
  throw std::logic_error("no principal-stretch form for " + model);
}

TEST_P(FiniteStrainModel, EnergyMatchesPrincipalStretchForm) {
  const MaterialLaw& m = law(GetParam());
  std::mt19937 rng(5);
  for (const Eigen::Vector3d& l : {Eigen::Vector3d(1.3, 0.8, 1.05), Eigen::Vector3d(2.0, 0.5, 0.7),
                                   Eigen::Vector3d(1.0, 1.0, 1.4)}) {
    const Mat3 F = random_rotation(rng) * l.asDiagonal() * random_rotation(rng).transpose();
    const double reference = principal_energy(m.name(), l);
    EXPECT_NEAR(stress(m, F).psi, reference, 1e-12 * reference) << l.transpose();
  }
}

INSTANTIATE_TEST_SUITE_P(Materials, FiniteStrainModel,
                         ::testing::ValuesIn(finite_strain_law_names()),
                         [](const auto& info) { return info.param; });

TEST(LinearElastic, EnergyIsTheQuadraticForm) {
  const MaterialLaw& m = law("linear_elastic");
  const Mat3 F = Eigen::Vector3d(1.01, 0.99, 1.02).asDiagonal();  // eps = diag(.01, -.01, .02)
  const double tr = 0.02;
  EXPECT_NEAR(stress(m, F).psi, kMu * (1e-4 + 1e-4 + 4e-4) + 0.5 * kLambda * tr * tr, 1e-15);
  EXPECT_NEAR(stress(m, F).P(2, 2), kLambda * tr + 2 * kMu * 0.02, 1e-14);
  // A pure rotation strains the linear law (it is not objective), so a 90-degree turn does.
  EXPECT_GT(stress(m, rotation(Eigen::Vector3d::UnitZ(), M_PI / 2)).psi, kMu);
}

TEST(Corotational, RotatedSmallStrainHasTheRotatedLinearStress) {
  // F = Q (I + eps) with eps symmetric: S = I + eps, R = Q, P = Q sigma_linear(eps).
  const MaterialLaw& m = law("corotational");
  Mat3 eps;
  eps << 0.02, 0.01, -0.005, 0.01, -0.01, 0.003, -0.005, 0.003, 0.015;
  const Mat3 Q = rotation(Eigen::Vector3d(1, 2, 3), 2.9);  // near a half turn
  const Mat3 sigma = kLambda * eps.trace() * Mat3::Identity() + 2 * kMu * eps;
  EXPECT_LT(relative_error(stress(m, Q * (Mat3::Identity() + eps)).P, Q * sigma), 1e-13);
}

TEST(Corotational, LargeStretchStressInPrincipalForm) {
  // F = Q1 diag(l) Q2^T: R = Q1 Q2^T, S = Q2 diag(l) Q2^T, so P = Q1 diag(s) Q2^T with
  // s_i = lambda sum_j (l_j - 1) + 2 mu (l_i - 1).
  const MaterialLaw& m = law("corotational");
  const Eigen::Vector3d l(3.0, 0.2, 1.5);
  const Mat3 Q1 = rotation(Eigen::Vector3d(0.3, -1, 2), 2.5),
             Q2 = rotation(Eigen::Vector3d(1, 1, 0), -1.2);
  Eigen::Vector3d principal;
  for (int i = 0; i < 3; ++i) principal(i) = kLambda * (l.sum() - 3) + 2 * kMu * (l(i) - 1);
  const Mat3 F = Q1 * l.asDiagonal() * Q2.transpose();
  EXPECT_LT(relative_error(stress(m, F).P, Q1 * principal.asDiagonal() * Q2.transpose()), 1e-14);
}

TEST(NeoHookean, CauchyStressInPrincipalStretches) {
  // sigma_i = (mu (l_i^2 - 1) + lambda ln J) / J on the principal axes.
  const MaterialLaw& m = law("neo_hookean");
  const Eigen::Vector3d l(1.4, 0.9, 0.75);
  const Mat3 Q = rotation(Eigen::Vector3d(-1, 0.5, 2), 0.7);
  const Mat3 F = Q * l.asDiagonal() * Q.transpose();
  const double J = l.prod();
  Eigen::Vector3d principal;
  for (int i = 0; i < 3; ++i) principal(i) = (kMu * (l(i) * l(i) - 1) + kLambda * std::log(J)) / J;
  const Mat3 reference = Q * principal.asDiagonal() * Q.transpose();
  EXPECT_LT(relative_error(cauchy_stress(m, F), reference), 1e-13);
}

TEST(VonMises, UniaxialAndHydrostatic) {
  EXPECT_NEAR(von_mises(Eigen::Vector3d(5.0, 0, 0).asDiagonal()), 5.0, 1e-14);
  EXPECT_NEAR(von_mises(-2.0 * Mat3::Identity()), 0.0, 1e-14);
  Mat3 shear = Mat3::Zero();
  shear(0, 1) = shear(1, 0) = 1.0;
  EXPECT_NEAR(von_mises(shear), std::sqrt(3.0), 1e-14);
}

// Every law of the registry has its test law here (make_law), named as registered.
TEST(MaterialRegistry, EveryRegisteredLawIsTestedAndNamedAsRegistered) {
  ASSERT_FALSE(material_law_names().empty());
  for (const std::string& name : material_law_names()) {
    std::shared_ptr<const MaterialLaw> made;
    EXPECT_NO_THROW(made = make_law(name, elastic_constants_from_lame(kMu, kLambda))) << name;
    if (made) EXPECT_EQ(made->name(), name);
  }
}

// A law's keys as its key table prints them (the resolved deck's material map).
std::map<std::string, double> printed_keys(const MaterialLaw& m) {
  YAML::Emitter out;
  out << YAML::BeginMap;
  print_material_law(out, m);
  out << YAML::EndMap;
  std::map<std::string, double> keys;
  for (const auto& item : YAML::Load(out.c_str()))
    keys[item.first.Scalar()] = item.second.as<double>();
  return keys;
}

// Every law prints, from its key table, keys that read back as the same law: the same keys and
// values printed again, the same stress at a finite strain.
TEST(MaterialRegistry, EveryLawPrintsKeysThatReadBackTheSameLaw) {
  const Mat3 F = Eigen::Vector3d(1.3, 0.9, 1.1).asDiagonal();
  for (const std::string& name : all_law_names()) {
    const std::map<std::string, double> printed = printed_keys(law(name));
    EXPECT_FALSE(printed.empty()) << name;
    const auto back = make_material_law(name, printed);
    EXPECT_EQ(printed_keys(*back), printed) << name;
    EXPECT_LT(relative_error(stress(*back, F).P, stress(law(name), F).P), 1e-14) << name;
  }
}

// The message lists the registry's laws, in order.
TEST(MaterialRegistry, UnknownModelListsTheRegisteredNames) {
  std::string names;
  for (const std::string& name : all_law_names()) names += (names.empty() ? "" : ", ") + name;
  try {
    make_material_law("ogden", {{"mu", kMu}, {"lambda", kLambda}});
    FAIL() << "no error for an unknown model";
  } catch (const InputError& e) {
    EXPECT_NE(
        std::string(e.what()).find("material.model: unknown name 'ogden' (valid: " + names + ")"),
        std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace hs
