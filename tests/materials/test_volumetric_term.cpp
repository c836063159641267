// The volumetric term k/2 (ln J)^2 that the nodal-pressure element integrates per node: its
// stress and tangent against differences of its energy, and a law less the term plus the term
// is the law.
#include <gtest/gtest.h>

#include <random>

#include "material_fixtures.hpp"
#include "materials/volumetric_term.hpp"

namespace hs {
namespace {

using namespace material_fixtures;

class VolumetricTermLaw final : public MaterialLaw {
 public:
  explicit VolumetricTermLaw(double k) : k_(k) {}
  std::string name() const override { return "volumetric_term"; }
  StressResult stress(const Mat3& H, bool t) const override { return volumetric_term(k_, H, t); }
  const ElasticConstants& elastic_constants() const override { return constants_; }
  std::string derived_values() const override { return ""; }

 private:
  double k_;
  ElasticConstants constants_;
};

TEST(VolumetricTerm, StressAndTangentAreTheDerivativesOfTheEnergy) {
  std::mt19937 rng(7);
  const VolumetricTermLaw term(3.0e6);
  for (int trial = 0; trial < 5; ++trial) {
    const Mat3 F = random_F(rng, 0.3);
    const StressResult s = stress(term, F);
    EXPECT_LT(relative_error(s.P, fd_stress(term, F, 1e-6)), 1e-7);
    EXPECT_LT(relative_error(s.A, fd_tangent(term, F, 1e-6)), 1e-7);
  }
}

TEST(VolumetricTerm, SmallStrainFormIsTheLinearElasticDilatationEnergy) {
  std::mt19937 rng(3);
  const Mat3 H = random_F(rng, 0.01) - Mat3::Identity();
  const StressResult s = volumetric_term(4e6, H, true, true);
  EXPECT_NEAR(s.psi, 2e6 * H.trace() * H.trace(), 1e-12 * s.psi);
  EXPECT_LT(relative_error(s.P, 4e6 * H.trace() * Mat3::Identity()), 1e-14);
  const VolumetricValues v = volumetric_function(4e6, 0.01, true);
  EXPECT_DOUBLE_EQ(v.U, 2e6 * 1e-4);
  EXPECT_DOUBLE_EQ(v.dU, 4e4);
  EXPECT_DOUBLE_EQ(v.d2U, 4e6);
}

TEST(VolumetricTerm, FunctionOfJAgreesWithTheTensorForm) {
  const double k = 2.5e6;
  for (double J : {0.7, 0.999, 1.0, 1.3}) {
    const VolumetricValues v = volumetric_function(k, J - 1);
    const Mat3 H = (std::cbrt(J) - 1) * Mat3::Identity();
    EXPECT_NEAR(v.U, volumetric_term(k, H, false).psi, 1e-9 * k);
    const double h = 1e-6;
    EXPECT_NEAR(
        v.dU, (volumetric_function(k, J - 1 + h).U - volumetric_function(k, J - 1 - h).U) / (2 * h),
        1e-6 * k);
    EXPECT_NEAR(
        v.d2U,
        (volumetric_function(k, J - 1 + h).dU - volumetric_function(k, J - 1 - h).dU) / (2 * h),
        1e-5 * k);
  }
}

// Every law that declares the term: less it, its bulk stiffness at F = I drops by k (what stays
// is of the order of mu), and less it plus it is the law, stress and tangent.
TEST(VolumetricTerm, LawLessTheTermPlusTheTermIsTheLaw) {
  std::mt19937 rng(11);
  int laws = 0;
  for (const std::string& name : all_law_names()) {
    const auto law = make_law(name, elastic_constants_from_E_nu(1e6, 0.4999));
    if (!law->has_volumetric_term()) continue;
    ++laws;
    const WithoutVolumetricTerm rest(law);
    EXPECT_FALSE(rest.has_volumetric_term());
    EXPECT_GT(law->volumetric_modulus(), 1e9);  // kappa or lambda at nu = 0.4999
    const Mat3 F = random_F(rng, 0.2);
    const StressResult full = stress(*law, F), part = stress(rest, F);
    const StressResult term =
        volumetric_term(law->volumetric_modulus(), F - Mat3::Identity(), true, law->small_strain());
    EXPECT_LT(relative_error(part.P + term.P, full.P), 1e-12) << name;
    EXPECT_LT(relative_error(part.A + term.A, full.A), 1e-12) << name;
    EXPECT_NEAR(part.psi + term.psi, full.psi, 1e-12 * std::abs(full.psi)) << name;
    // Bulk stiffness at rest, d2 psi/dJ2 along F = J^(1/3) I: the law's k + mu-ish, the rest's
    // of the order of mu (1e6 / 3 here), not kappa (1.7e9).
    const Tangent A0 = stress(rest, Mat3::Identity()).A;
    double bulk = 0;
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) bulk += A0(4 * i, 4 * k) / 9;
    EXPECT_LT(std::abs(bulk), 1e6) << name;
  }
  EXPECT_GE(laws, 5);  // neo_hookean, mooney_rivlin, yeoh, gent, linear_elastic
}

}  // namespace
}  // namespace hs
