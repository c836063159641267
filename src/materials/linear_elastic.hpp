// Small-strain linear elasticity (docs/formulation.md, "Linear elastic"), model linear_elastic.
#pragma once

#include "materials/elastic_constants.hpp"

namespace hs {

// eps = sym(H), P = sigma = lambda tr(eps) I + 2 mu eps (H = F - I; A = 0 unless with_tangent).
StressResult linear_elastic(double mu, double lambda, const Mat3& H, bool with_tangent);

inline constexpr char kLinearElasticName[] = "linear_elastic";

class LinearElasticLaw final : public ConstantsOnlyLaw<kLinearElasticName, linear_elastic> {
 public:
  static std::shared_ptr<const MaterialLaw> make(const DeckReader& r, const YAML::Node& node,
                                                 const std::string& key, const Parameters& read) {
    return std::make_shared<LinearElasticLaw>(resolve_elastic_constants(r, node, key, read));
  }
  using ConstantsOnlyLaw::ConstantsOnlyLaw;
  bool has_volumetric_term() const override { return true; }  // lambda/2 tr(eps)^2
  double volumetric_modulus() const override { return constants_.lambda; }
  // Small strain does not tell the configurations apart: its P already is sigma.
  Mat3 cauchy_stress(const Mat3& F) const override;
  bool tangent_always_definite() const override { return true; }
  bool small_strain() const override { return true; }
};

}  // namespace hs
