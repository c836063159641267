// Step 3 of the inverse controller (docs/control.md), shared by the full model's controller
// and the reduced one: the actuation changes dl from the dense QP
//   min 1/2 |W dl + delta|^2 + eps/2 |dl|^2
// under each actuator's bounds: its multiplier's range, its change per step (counted from the
// step's origin) and its measure's growth since rest (linear in dl through `growth`).
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "deck/config.hpp"

namespace hs {

// Where an actuator stands when the QP is set up.
struct ActuatorPosition {
  double multiplier = 0;  // now
  double origin = 0;      // at the step's first QP: the change per step counts from there
  double grown = 0;       // its measure's change since rest, the free step's included
};

struct ActuationChange {
  Eigen::VectorXd dl;  // zero when the QP was not solved
  bool solved = false;
  std::string status;
  double kkt_residual = 0;
  std::vector<bool> saturated;  // per actuator: a bound of it is active
};

// W: weighted effector rows x actuators; delta: their weighted distance to the targets;
// growth(a, b): actuator a's measure change per unit of actuation b.
ActuationChange solve_actuation_qp(const Eigen::MatrixXd& W, const Eigen::VectorXd& delta,
                                   const Eigen::MatrixXd& growth,
                                   const std::vector<ActuatorConfig>& bounds,
                                   const std::vector<ActuatorPosition>& at, double regularization);

}  // namespace hs
