#include "solvers/constraints/pressure_limited_cavity.hpp"

#include <algorithm>

namespace hs {

PressureLimitedCavity::PressureLimitedCavity(const CavityConfig& config, ConstraintContext& context)
    : Cavity(config, context),
      max_pressure_(config.max_pressure),
      added_volume_(config.added_volume.value_or(0.0)),
      stiffness_(config.max_pressure / reference_measure()) {
  prescribe(Control::own_law, reference_measure());  // its target is the delivered volume
}

double PressureLimitedCavity::first_state_target(double tau) const {
  return reference_measure() + tau * added_volume_;
}

bool PressureLimitedCavity::valve_open() const {
  return multiplier() - max_pressure_ >= volume_term();
}

double PressureLimitedCavity::law_residual() const {
  return std::max(multiplier() - max_pressure_, volume_term());
}

void PressureLimitedCavity::law_linearization(double& alpha, double& b) const {
  alpha = valve_open() ? 0.0 : stiffness_;
  b = valve_open() ? 1.0 : 0.0;
}

nlohmann::json PressureLimitedCavity::report() const {
  nlohmann::json j = Cavity::report();
  j["max_pressure"] = max_pressure_;
  j["delivered_volume"] = target();
  // Open where the pressure is at its limit: what the pump delivered and the cavity does not
  // hold has left through the valve.
  j["valve_open"] = multiplier() >= max_pressure_ * (1 - 1e-9);
  j["vented_volume"] = std::max(target() - measure(), 0.0);
  return j;
}

}  // namespace hs
