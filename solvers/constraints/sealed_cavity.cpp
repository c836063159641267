#include "solvers/constraints/sealed_cavity.hpp"

namespace hs {

SealedCavity::SealedCavity(const CavityConfig& config, ConstraintContext& context)
    : Cavity(config, context),
      gas_(config.kind == CavityKind::sealed_gas),
      atmospheric_pressure_(config.atmospheric_pressure) {
  prescribe(Control::own_law, 0);
  if (gas_) {
    set_multiplier(config.initial_pressure);
    gas_constant_ = (config.initial_pressure + atmospheric_pressure_) * measure();
  }
}

double SealedCavity::law_residual() const {
  if (gas_) return (multiplier() + atmospheric_pressure_) * measure() - gas_constant_;
  return measure() - reference_measure();
}

void SealedCavity::law_linearization(double& alpha, double& b) const {
  alpha = gas_ ? multiplier() + atmospheric_pressure_ : 1.0;
  b = gas_ ? measure() : 0.0;
}

double SealedCavity::law_scale() const { return gas_ ? gas_constant_ : reference_measure(); }

}  // namespace hs
