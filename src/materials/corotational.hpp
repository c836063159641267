// Corotational linear elasticity (docs/formulation.md, "Corotational"), model corotational.
#pragma once

#include "materials/elastic_constants.hpp"

namespace hs {

// F = R S, psi = mu |S - I|^2 + lambda/2 tr(S - I)^2, P = R dpsi/dS (H = F - I).
// psi = +inf, P = A = NaN for det F <= 0; A = 0 unless with_tangent.
StressResult corotational(double mu, double lambda, const Mat3& H, bool with_tangent);

class CorotationalLaw final : public ElasticLaw {
 public:
  static constexpr const char* kName = "corotational";
  static std::vector<std::string> keys() { return kElasticConstantKeys; }
  static std::shared_ptr<const MaterialLaw> parse(const DeckReader& r, const YAML::Node& node,
                                                  const std::string& key);

  using ElasticLaw::ElasticLaw;
  std::string name() const override { return kName; }
  StressResult stress(const Mat3& H, bool with_tangent) const override;
};

}  // namespace hs
