// A small dense convex QP, the inner problem of the inverse controller (docs/control.md,
// "The QP solver"):
//
//   minimise 1/2 x^T H x + f^T x   subject to   A x >= b   (row by row),
//
// H symmetric positive definite (the controller adds its regularisation), n and m small
// (a few actuators, a few bounds each). Solved by the dual active-set method of Goldfarb
// and Idnani: start at the unconstrained minimum, add the most violated constraint, and
// move primal and dual variables together so that every iterate is optimal for the
// constraints in the active set; a constraint whose multiplier would turn negative leaves.
// It needs no feasible starting point, ends in finitely many steps, and proves
// infeasibility when a violated constraint cannot be satisfied.
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

namespace hs {

struct QpResult {
  Eigen::VectorXd x;            // the minimiser (the unconstrained one if not solved)
  Eigen::VectorXd multipliers;  // one per constraint row, >= 0, zero off the active set
  bool solved = false;
  std::string status;  // "optimal", "infeasible: ...", "H is not positive definite", ...
  int iterations = 0;  // constraints added or dropped
  // Largest of the scaled KKT conditions at (x, multipliers): stationarity
  // |H x + f - A^T mu|, primal violation max(b - A x, 0), complementarity |mu_i (A x - b)_i|,
  // each divided by the size of the terms it is made of, x measured by the larger of |x|
  // and |H^-1 f| (docs/control.md).
  double kkt_residual = 0;
  std::vector<int> active;  // rows in the final active set (multiplier > 0)
};

// Dimensions must agree (std::invalid_argument otherwise). Non-finite data or an H that
// is not positive definite give solved = false with the reason in status.
QpResult solve_qp(const Eigen::MatrixXd& H, const Eigen::VectorXd& f, const Eigen::MatrixXd& A,
                  const Eigen::VectorXd& b);

// The scaled KKT residual of a candidate (x, mu), as reported in QpResult.
double qp_kkt_residual(const Eigen::MatrixXd& H, const Eigen::VectorXd& f, const Eigen::MatrixXd& A,
                       const Eigen::VectorXd& b, const Eigen::VectorXd& x,
                       const Eigen::VectorXd& mu);

}  // namespace hs
