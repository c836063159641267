// A reduced answer's error, estimated from the full model's residual (docs/reduced_models.md,
// "Each answer's error"). At the answer's field u = Phi q and actuation, the full equations'
// residual R(u) is what the reduced space left out; the Newton step that would take u to the
// full model's equilibrium at the same actuation is du = -J^-1 R, and it moves the effectors'
// row r (an effector's position along x, y or z) by
//   dx_r = e_r^T du = -z_r^T R,   J^T z_r = e_r,
// the residual weighted by the row's influence function z_r (a dual-weighted residual). J is
// the full tangent at the training sample nearest the answer's actuation (its follower
// stiffness included, the liquid weight's dependence on the volume left out), each z_r solved
// once per training sample when the model is loaded: an answer then costs one evaluation of
// the full residual and a dot product per row. The indicator is the first term of the error's
// expansion; the training measures it against the full model on the held-back samples and
// states the ratio (the calibration).
#pragma once

#include <petscvec.h>

#include <Eigen/Dense>
#include <vector>

#include "solvers/constraints/constraint_set.hpp"
#include "solvers/problem.hpp"
#include "solvers/reduced/reduced_system.hpp"

namespace hs {

class ResidualErrorIndicator {
 public:
  // Factors the full tangent at each of the system's training samples and solves for the
  // influence function of each row (`rows`: 3 per effector, x y z). `actuators`: the model's
  // actuators (constraint indices, in the model's order). The constraints are put back as they
  // were. Throws SolveError when a training sample's tangent cannot be evaluated or factored.
  ResidualErrorIndicator(Problem& problem, ConstraintSet& constraints, const ReducedSystem& system,
                         const std::vector<int>& actuators, const std::vector<Vec>& rows);

  // dx (one entry per row): the estimated change of each row from u, the reduced answer's
  // whole field at the constraints' current multipliers (the actuation `lambda`, the model's
  // actuators), to the full model's equilibrium. False (dx untouched) where the full residual
  // cannot be evaluated there (an inverted element). The constraints are put back.
  bool estimate(Vec u, const Eigen::VectorXd& lambda, Eigen::VectorXd& dx);

  // The largest distance an effector moves by dx (3 rows each): the answer's stated error.
  static double largest_move(const Eigen::VectorXd& dx);

  double setup_seconds() const { return setup_s_; }

 private:
  ConstraintSet& constraints_;
  const ReducedSystem& system_;
  std::vector<Eigen::MatrixXd> influence_;  // per training sample: local dofs x rows
  VecHandle residual_;
  double setup_s_ = 0;
};

}  // namespace hs
