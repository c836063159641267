#include "solvers/constraints/sealed_cavity.hpp"

namespace hs {

SealedCavity::SealedCavity(const CavityConfig& config, Problem& problem,
                           const std::string& deck_path)
    : Cavity(config, problem, deck_path),
      gas_(config.kind == CavityKind::sealed_gas),
      atmospheric_pressure_(config.atmospheric_pressure) {
  control = Control::own_law;
  if (gas_) {
    lambda = config.initial_pressure;
    gas_constant_ = (config.initial_pressure + atmospheric_pressure_) * measure;
  }
}

double SealedCavity::law_residual() const {
  if (gas_) return (lambda + atmospheric_pressure_) * measure - gas_constant_;
  return measure - reference_measure;
}

void SealedCavity::law_linearization(double& alpha, double& b) const {
  alpha = gas_ ? lambda + atmospheric_pressure_ : 1.0;
  b = gas_ ? measure : 0.0;
}

double SealedCavity::law_scale() const { return gas_ ? gas_constant_ : reference_measure; }

}  // namespace hs
