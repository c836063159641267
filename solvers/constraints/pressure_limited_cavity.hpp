// A pressure-limited cavity: a pump delivers a volume (added_volume, ramped over the first
// state) through a relief valve that opens at max_pressure. Either the valve is shut and the
// cavity holds what the pump delivered, V = V_t, at a pressure lambda <= p_max; or it is open
// and lambda = p_max, the cavity holding less, V <= V_t. Both cases are the root of one
// semismooth equation, in Pa:
//   c(u, lambda) = max(lambda - p_max, k (V(u) - V_t)) = 0,   k = p_max / V_0
// linearised on the branch that is the larger (b = 1 on the valve's, alpha = k on the
// pump's). docs/cavities.md, "Pressure-limited cavities".
#pragma once

#include "solvers/constraints/cavity.hpp"

namespace hs {

class PressureLimitedCavity : public Cavity {
 public:
  PressureLimitedCavity(const CavityConfig& config, ConstraintContext& context);

  double first_state_target(double tau) const override;
  nlohmann::json report() const override;

 protected:
  double law_residual() const override;
  void law_linearization(double& alpha, double& b) const override;
  double law_scale() const override { return max_pressure_; }

 private:
  // Whether the valve's branch is the larger: the valve is open (or would be).
  bool valve_open() const;
  double volume_term() const { return stiffness_ * (measure() - target()); }

  double max_pressure_;
  double added_volume_;
  double stiffness_;  // k: Pa per m^3 of volume error
};

}  // namespace hs
