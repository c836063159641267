// Newton's method for R(u; s) = 0 through PETSc's SNES (line search), with the linear
// solver from its options (prefix hs_newton_, solvers/solver_options.hpp): MUMPS by default,
// CG/GMRES + GAMG with the rigid-body near-null space as the "gamg" preset. Options come,
// lowest precedence first, from the preset, the deck's solver.petsc_options and the command
// line.
#pragma once

#include <petscsnes.h>

#include <string>

#include "deck/config.hpp"
#include "solvers/problem.hpp"
#include "solvers/solver_options.hpp"
#include "solvers/stepping/nonlinear_solver.hpp"

namespace hs {

class NewtonSolver : public NonlinearSolver {
 public:
  // The preset is chosen for the tangent's kind (run_setup.cpp works it out for a deck).
  NewtonSolver(Problem& problem, const SolverConfig& solver, TangentKind tangent);
  NewtonSolver(const NewtonSolver&) = delete;
  NewtonSolver& operator=(const NewtonSolver&) = delete;

  // Solves at load factor s starting from u (which must satisfy the constraints at s).
  NewtonResult solve(Vec u, double s) override;

  // Unless snes_atol was given (deck or command line): accept a residual below 1e-9 of the full
  // external load's norm. A relative test alone cannot pass when a step starts near its solution
  // (time steps, small load increments): its floor is round-off, not the load.
  void scale_absolute_tolerance(double load_norm);
  double solve_seconds() const override { return solve_s_; }  // SNESSolve minus assembly
  // du = -J(u)^-1 R(u; s) by the SNES's own linear solver; false on an inverted element or a
  // failed linear solve.
  bool newton_step(Vec u, double s, Vec du, std::vector<double>& dmultipliers) override;
  SNES snes() const { return snes_; }

 private:
  // SNES at the volume multipliers as they are (solvers/incompressibility.hpp repeats it for
  // exactly incompressible bodies).
  NewtonResult solve_once(Vec u);
  static PetscErrorCode form_residual(SNES, Vec u, Vec R, void* ctx);
  static PetscErrorCode form_jacobian(SNES, Vec u, Mat J, Mat P, void* ctx);
  static PetscErrorCode form_objective(SNES, Vec u, PetscReal* energy, void* ctx);
  // With obstacles: shortens the Newton step so that no contact node crosses into one
  // (Problem::contact_step_limit), before the line search.
  static PetscErrorCode limit_step(SNESLineSearch, Vec u, Vec y, PetscBool* changed, void* ctx);
  // With contact: shortens the line search's answer w the same way, from u, where the search
  // went beyond the limited step (l2 extrapolates): past a triangle or an edge (self-contact's
  // distances are unsigned, so no residual would refuse it) or into an obstacle (whose
  // residual would, ending the solve).
  static PetscErrorCode limit_answer(SNESLineSearch, Vec u, Vec y, Vec w, PetscBool* changed_y,
                                     PetscBool* changed_w, void* ctx);
  // PETSc's test, and convergence when the residual is down to the round-off of its own
  // evaluation (Problem::residual_roundoff), checked once it is 1e-6 of the first.
  static PetscErrorCode converged(SNES, PetscInt it, PetscReal xnorm, PetscReal snorm,
                                  PetscReal fnorm, SNESConvergedReason* reason, void* ctx);

  Problem& problem_;
  SolverOptions options_;  // before the SNES: it outlives it
  SnesHandle snes_;
  MatHandle J_;
  VecHandle R_;
  double load_ = 0;
  double solve_s_ = 0;
  double first_norm_ = 0;        // of this solve's first residual
  double start_floor_ = 0;       // its round-off floor (Problem::residual_roundoff)
  double roundoff_ = -1;         // the floor it converged at, -1 when it converged otherwise
  bool atol_scaled_ = false;     // by a load (scale_absolute_tolerance)
  bool contact_search_ = false;  // the line search is chosen per solve (obstacles)
  int pattern_version_ = 0;      // the tangent pattern the preconditioner was set up for
  void reset_if_pattern_grew();
  bool volume_monitor_ = false;  // -hs_volume_monitor: a line per raise of the multipliers
};

}  // namespace hs
