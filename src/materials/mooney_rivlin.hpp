// Compressible Mooney-Rivlin on the isochoric invariants (docs/formulation.md, "Mooney-Rivlin"),
// model mooney_rivlin: keys E, nu or mu, lambda (the bulk modulus kappa = lambda + 2 mu / 3)
// and c1, c2 (default c1 = mu / 2, c2 = 0: then it is neo-Hookean-like).
#pragma once

#include <optional>

#include "materials/elastic_constants.hpp"

namespace hs {

// psi = c1 (I1b - 3) + c2 (I2b - 3) + kappa/2 (ln J)^2 (H = F - I); psi = +inf, P = A = NaN for
// det F <= 0; A = 0 unless with_tangent.
StressResult mooney_rivlin(double c1, double c2, double kappa, const Mat3& H, bool with_tangent);

struct MooneyRivlinParameters : ElasticConstants {
  std::optional<double> c1;  // none: mu / 2
  double c2 = 0;
};

class MooneyRivlinLaw final : public ElasticLaw {
 public:
  static constexpr const char* kName = "mooney_rivlin";
  using Parameters = MooneyRivlinParameters;
  // The elastic constants', c1 and c2.
  static const LawKeyTable<Parameters>& keys();
  static std::shared_ptr<const MaterialLaw> make(const DeckReader& r, const YAML::Node& node,
                                                 const std::string& key, const Parameters& read);
  Parameters parameters() const { return {constants_, c1_, c2_}; }

  MooneyRivlinLaw(const ElasticConstants& constants, double c1, double c2)
      : ElasticLaw(constants), c1_(c1), c2_(c2) {}
  std::string name() const override { return kName; }
  StressResult stress(const Mat3& H, bool with_tangent) const override;
  bool has_volumetric_term() const override { return true; }
  double volumetric_modulus() const override {
    return constants_.lambda + 2.0 * constants_.mu / 3.0;
  }

  double c1() const { return c1_; }
  double c2() const { return c2_; }

 private:
  double c1_, c2_;
};

}  // namespace hs
