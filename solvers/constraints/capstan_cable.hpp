// A cable with Coulomb friction where it turns through its eyelets (the capstan equation,
// src/actuators/capstan.hpp): the motor's tension T falls by exp(-mu theta) at each turn on
// the way to the cable's far end. Its multiplier is the motor's tension, its measure the
// cable's length with a minus sign as for the frictionless cable; its forces are no longer
// the gradient of the length, and its stiffness -T dF/du couples every pair of its points and
// is not symmetric (with friction the tangent needs an LU factorization or GMRES, not CG or
// Cholesky). The friction is taken as sliding towards the motor (the cable is being pulled
// in), which is the state of a tendon that is being tightened.
#pragma once

#include <vector>

#include "solvers/constraints/cable.hpp"

namespace hs {

class CapstanCable : public Cable {
 public:
  // Collective; config.friction > 0.
  CapstanCable(const CableConfig& config, ConstraintContext& context);

  void forces(Vec u, Vec g) const override;
  void add_load(Vec u, double s, Vec load) override;
  void set_stiffness(Vec u, Problem& problem) override;
  bool symmetric_stiffness() const override { return false; }
  nlohmann::json report() const override;

 private:
  // The forces of a unit motor tension on the material points (3 each) on configuration u.
  std::vector<double> point_forces(Vec u) const;

  double friction_;
  int coupling_ = -1;  // rank 0: one block over every material point's dofs
};

}  // namespace hs
