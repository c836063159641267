// A sealed cavity: no pump, its pressure follows from its own law.
//   sealed_gas     isothermal ideal gas, (lambda + p_atm) V(u) = (p_0 + p_atm) V_0
//   sealed_volume  an incompressible liquid, V(u) = V_0
// with lambda the gauge pressure, p_0 its value on the undeformed mesh (volume V_0).
#pragma once

#include "solvers/constraints/cavity.hpp"

namespace hs {

class SealedCavity : public Cavity {
 public:
  SealedCavity(const CavityConfig& config, ConstraintContext& context);

 protected:
  double law_residual() const override;
  void law_linearization(double& alpha, double& b) const override;
  double law_scale() const override;

 private:
  bool gas_ = false;
  double atmospheric_pressure_ = 0;
  double gas_constant_ = 0;  // (p_0 + p_atm) V_0
};

}  // namespace hs
