// Compressible Yeoh on the isochoric first invariant (docs/formulation.md, "Yeoh"), model yeoh,
// for silicones whose published fits are Yeoh's: keys C1 > 0, C2, C3 (Pa; C2, C3 default 0, may
// be negative) and nu. C1 gives the small-strain shear modulus mu = 2 C1, nu the bulk modulus
// kappa = lambda + 2 mu / 3 = 2 mu (1 + nu) / (3 (1 - 2 nu)). With C2 = C3 = 0 it is
// Mooney-Rivlin with c1 = C1, c2 = 0.
#pragma once

#include "materials/elastic_constants.hpp"

namespace hs {

// psi = C1 x + C2 x^2 + C3 x^3 + kappa/2 (ln J)^2, x = I1b - 3 (H = F - I); psi = +inf,
// P = A = NaN for det F <= 0; A = 0 unless with_tangent.
StressResult yeoh(double C1, double C2, double C3, double kappa, const Mat3& H, bool with_tangent);

// The smallest I1b - 3 > 0 at which dpsi/dI1b = C1 + 2 C2 x + 3 C3 x^2 reaches 0 (C1 > 0), past
// which the fit softens under further stretch; +inf if it stays positive.
double yeoh_softening_onset(double C1, double C2, double C3);

struct YeohParameters {
  double C1 = 0, C2 = 0, C3 = 0, nu = 0;
};

class YeohLaw final : public MaterialLaw {
 public:
  static constexpr const char* kName = "yeoh";
  using Parameters = YeohParameters;
  static const LawKeyTable<Parameters>& keys();  // C1, C2, C3, nu
  static std::shared_ptr<const MaterialLaw> make(const DeckReader& r, const YAML::Node& node,
                                                 const std::string& key, const Parameters& read);
  Parameters parameters() const { return {C1(), C2_, C3_, constants_.nu}; }

  // C1 = small_strain.mu / 2 (small_strain from elastic_constants_from_mu_nu(2 C1, nu)).
  YeohLaw(const ElasticConstants& small_strain, double C2, double C3)
      : constants_(small_strain), C2_(C2), C3_(C3) {}
  std::string name() const override { return kName; }
  StressResult stress(const Mat3& H, bool with_tangent) const override;
  bool has_volumetric_term() const override { return true; }
  double volumetric_modulus() const override {
    return constants_.lambda + 2.0 * constants_.mu / 3.0;
  }
  const ElasticConstants& elastic_constants() const override { return constants_; }
  // mu, lambda, E, and the softening onset where there is one.
  std::string derived_values() const override;

  double C1() const { return constants_.mu / 2; }
  double C2() const { return C2_; }
  double C3() const { return C3_; }

 private:
  ElasticConstants constants_;
  double C2_, C3_;
};

}  // namespace hs
