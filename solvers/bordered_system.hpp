// The block elimination of the bordered system of a linearization (docs/cavities.md):
//   [ J    -G ] [du     ]     [R]          J du = -R + G dlambda + Q eta
//   [ A     B ] [dlambda] = - [c],  with   eta_h = g_h^T du (hydraulic cavities, Q = W / V)
// One factorization of the sparse tangent J and the solves a = J^-1 R, Y_c = J^-1 g_c and
// Z_h = J^-1 q_h through it together, then a dense system S zeta = rhs of size m + m_h for
// zeta = [dlambda; eta], and du = -a + [Y Z] zeta. BorderedNewton solves it at every
// iteration; the inverse controller holds its actuators' rows (their dlambda is its input)
// and keeps the elimination for the response to each actuator.
#pragma once

#include <petscksp.h>

#include <Eigen/Dense>
#include <vector>

#include "solvers/constraints/constraint_set.hpp"
#include "solvers/petsc_handle.hpp"
#include "solvers/problem.hpp"

namespace hs {

class BorderedSystem {
 public:
  // The order in which the right-hand sides go through the factors together (one MatMatSolve).
  // Each caller keeps the order it had before the elimination was shared, so that its numbers
  // stay as they were bit for bit: the bordered Newton's, each constraint's g_c followed by its
  // q_c; the controller's, every g_c, then every q_h. (Whether MUMPS gives a column the same
  // last bits in either order was not measured.)
  enum class Order { per_constraint, g_then_q };

  BorderedSystem(const Problem& problem, const ConstraintSet& constraints, Order order);

  // With ksp's operators (factored here if they are not yet): a = J^-1 R and the columns Y, Z
  // of lin; adds the Krylov iterations to *iterations. False when a solve failed.
  bool solve(KSP ksp, Vec R, const ConstraintLinearization& lin, int* iterations = nullptr);
  // a = J^-1 R alone, with the operators and columns of the last solve().
  void solve_residual(KSP ksp, Vec R);
  // Forms and factors S: row c is c's control, alpha_c g_c^T du + b_c dlambda_c, or, where
  // held[c] (an actuator of the controller), dlambda_c itself; row m + w is eta_h - g_h^T du.
  void factor_dense(const ConstraintLinearization& lin, const std::vector<bool>& held = {});
  // The right-hand side of S for the step that removes the residual: -c_c + alpha_c g_c^T a
  // (0 where held) and g_h^T a.
  Eigen::VectorXd residual_rhs(const ConstraintLinearization& lin, const std::vector<double>& c,
                               const std::vector<bool>& held = {}) const;
  Eigen::VectorXd solve_dense(const Eigen::VectorXd& rhs) const { return lu_.solve(rhs); }
  Eigen::MatrixXd solve_dense(const Eigen::MatrixXd& rhs) const { return lu_.solve(rhs); }
  // out = -a + [Y Z] zeta: the displacement step of zeta.
  void step(const Eigen::VectorXd& zeta, Vec out);
  // out = [Y Z] zeta: the response to zeta alone (no residual).
  void response(const Eigen::VectorXd& zeta, Vec out);
  // The responses of the whole system to loads f_j (after factor_dense with `held`):
  // out_j = J^-1 f_j + [Y Z] zeta_j, with S zeta_j = -(alpha_c g_c^T J^-1 f_j, 0 where held;
  // g_h^T J^-1 f_j); the zeta_j as columns. False when a solve failed.
  bool load_responses(KSP ksp, const std::vector<Vec>& f, const ConstraintLinearization& lin,
                      const std::vector<bool>& held, const std::vector<Vec>& out,
                      Eigen::MatrixXd& zeta);

  int size() const { return static_cast<int>(columns_.size()); }  // m + m_h
  Vec a() const { return a_; }

 private:
  int m_ = 0;
  Order order_;
  VecHandle a_;
  VecArray Y_, Z_;             // per constraint; per constraint with a measure load (or null)
  std::vector<Vec> columns_;   // Y, then the Z of the weighted constraints
  std::vector<int> weighted_;  // the constraints with a measure load, in order
  Eigen::FullPivLU<Eigen::MatrixXd> lu_;
};

}  // namespace hs
