// The volumetric term k/2 (ln J)^2 that the hyperelastic laws of this code share (neo-Hookean
// with k = lambda; Mooney-Rivlin, Yeoh and Gent with the bulk modulus kappa), its small-strain
// form k/2 (tr eps)^2 (linear elasticity, k = lambda), and a law with that term taken out. The
// nodal-pressure element (docs/formulation.md, "Nearly incompressible bodies on P1 meshes")
// integrates the law without its stiff volumetric term per element and the term itself per node, on
// the volume ratio of the node's patch.
#pragma once

#include <memory>

#include "materials/material.hpp"

namespace hs {

// psi = k/2 (ln J)^2, P = k ln J F^-T, A = k [F^-T (x) F^-T - ln J D] (D_ijkl = F^-T_il F^-T_kj)
// at H = F - I; inverted_result() for det F <= 0. small_strain: psi = k/2 (tr H)^2, P = k tr H I,
// A = k I (x) I.
StressResult volumetric_term(double k, const Mat3& H, bool with_tangent, bool small_strain = false);

// U(J) = k/2 (ln J)^2 of a volume ratio J = 1 + J_minus_one, and its first two derivatives
// (from J - 1, so that a small volume change keeps its digits); small_strain: U = k/2 (J - 1)^2,
// J - 1 the linearised volume change.
struct VolumetricValues {
  double U = 0, dU = 0, d2U = 0;
};
VolumetricValues volumetric_function(double k, double J_minus_one, bool small_strain = false);

// `law` less its volumetric term (law.has_volumetric_term()): psi - k/2 (ln J)^2, with the
// law's name and constants; it has no volumetric term of its own.
class WithoutVolumetricTerm final : public MaterialLaw {
 public:
  explicit WithoutVolumetricTerm(std::shared_ptr<const MaterialLaw> law);
  std::string name() const override { return law_->name(); }
  StressResult stress(const Mat3& H, bool with_tangent) const override;
  const ElasticConstants& elastic_constants() const override { return law_->elastic_constants(); }
  bool small_strain() const override { return law_->small_strain(); }
  std::string derived_values() const override { return law_->derived_values(); }
  // The modulus taken out.
  double removed_modulus() const { return k_; }

 private:
  std::shared_ptr<const MaterialLaw> law_;
  double k_;
};

}  // namespace hs
