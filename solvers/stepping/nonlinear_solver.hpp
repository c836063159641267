// What a stepper asks of the equations it steps: solve them at a parameter from a start.
// NewtonSolver (SNES, the body alone) and BorderedNewton (with the constraints' multipliers)
// are the two today; a reduced model, or a solve that iterates an active set of contact, is
// one more class behind the same call, and no stepper changes.
#pragma once

#include <petscvec.h>

#include <string>
#include <vector>

namespace hs {

struct NewtonResult {
  bool converged = false;
  int iterations = 0;
  int linear_iterations = 0;
  double residual_norm = 0;
  std::string reason;  // PETSc's converged/diverged reason, or CONVERGED_ROUNDOFF
};

class NonlinearSolver {
 public:
  virtual ~NonlinearSolver() = default;
  // Solves at load factor s starting from u (which must satisfy the Dirichlet conditions at
  // s); on success u (and the solver's other unknowns, such as the multipliers) hold the
  // solution.
  virtual NewtonResult solve(Vec u, double s) = 0;
  // Seconds in the solves' own linear algebra (assembly not counted).
  virtual double solve_seconds() const = 0;
  // One Newton step from u at s, not taken: du and the multipliers' changes (the first-order
  // change of the solution were the equations' loads those of the residual at u). Collective.
  // False where this solver has none to give or its linear solve failed.
  virtual bool newton_step(Vec /*u*/, double /*s*/, Vec /*du*/,
                           std::vector<double>& /*dmultipliers*/) {
    return false;
  }
};

}  // namespace hs
