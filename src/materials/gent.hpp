// Compressible Gent on the isochoric first invariant (docs/formulation.md, "Gent"), model gent,
// for silicones that stiffen as their chains near full extension: keys E, nu or mu, lambda (the
// small-strain constants; the bulk modulus kappa = lambda + 2 mu / 3) and Jm > 0, the limit of
// I1b - 3. As Jm -> inf it becomes Mooney-Rivlin with c1 = mu / 2, c2 = 0.
#pragma once

#include "materials/elastic_constants.hpp"

namespace hs {

// psi = -mu Jm/2 ln(1 - (I1b - 3)/Jm) + kappa/2 (ln J)^2 (H = F - I); psi = +inf, P = A = NaN
// for det F <= 0 and outside the limiting chain (I1b - 3 >= Jm); A = 0 unless with_tangent.
StressResult gent(double mu, double Jm, double kappa, const Mat3& H, bool with_tangent);

struct GentParameters : ElasticConstants {
  double Jm = 0;
};

class GentLaw final : public ElasticLaw {
 public:
  static constexpr const char* kName = "gent";
  using Parameters = GentParameters;
  // The elastic constants' and Jm.
  static const LawKeyTable<Parameters>& keys();
  static std::shared_ptr<const MaterialLaw> make(const DeckReader& r, const YAML::Node& node,
                                                 const std::string& key, const Parameters& read);
  Parameters parameters() const { return {constants_, Jm_}; }

  GentLaw(const ElasticConstants& constants, double Jm) : ElasticLaw(constants), Jm_(Jm) {}
  std::string name() const override { return kName; }
  StressResult stress(const Mat3& H, bool with_tangent) const override;
  bool has_volumetric_term() const override { return true; }
  bool finite_wherever_oriented() const override { return false; }  // past Jm: undefined
  double volumetric_modulus() const override {
    return constants_.lambda + 2.0 * constants_.mu / 3.0;
  }

  double Jm() const { return Jm_; }

 private:
  double Jm_;
};

}  // namespace hs
