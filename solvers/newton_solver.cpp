#include "solvers/newton_solver.hpp"

#include "common/error.hpp"
#include "solvers/incompressibility.hpp"

namespace hs {
namespace {

// The preset's options; with contact without its line search, which solve() chooses per
// step unless the deck or the command line does.
std::map<std::string, std::string> newton_presets(const Problem& problem,
                                                  const SolverConfig& solver, TangentKind tangent) {
  auto options = preset_options(solver.preset, tangent);
  if (problem.has_contact()) options.erase("snes_linesearch_type");
  return options;
}

}  // namespace

NewtonSolver::NewtonSolver(Problem& problem, const SolverConfig& solver, TangentKind tangent)
    : problem_(problem),
      options_(kNewtonPrefix, solver, newton_presets(problem, solver, tangent),
               SolverOptions::Reach::every_object) {
  const OptionsScope scope(options_.database());  // the matrix's options too (-mat_view)
  J_ = MatHandle(problem.create_matrix(options_.factors_mixed()));
  R_ = VecHandle(problem.create_vector());
  volume_monitor_ = options_.get_unprefixed_bool("hs_volume_monitor", false);
  if (!options_.get_unprefixed_bool("hs_near_null_space", true))
    HS_PETSC(MatSetNearNullSpace(J_, nullptr));
  HS_PETSC(SNESCreate(problem.comm(), snes_.out()));
  options_.attach(reinterpret_cast<PetscObject>(snes_.get()));
  HS_PETSC(SNESSetOptionsPrefix(snes_, kNewtonPrefix));
  HS_PETSC(SNESSetFunction(snes_, R_, form_residual, this));
  HS_PETSC(SNESSetJacobian(snes_, J_, J_, form_jacobian, this));
  if (problem.has_potential()) HS_PETSC(SNESSetObjective(snes_, form_objective, this));
  if (problem.has_contact()) {
    SNESLineSearch search;
    HS_PETSC(SNESGetLineSearch(snes_, &search));
    HS_PETSC(SNESLineSearchSetPreCheck(search, limit_step, this));
    HS_PETSC(SNESLineSearchSetPostCheck(search, limit_answer, this));
    contact_search_ = !options_.has("snes_linesearch_type");
  }
  HS_PETSC(SNESSetFromOptions(snes_));
  // -hs_newton_roundoff false: PETSc's test alone
  if (options_.get_bool("roundoff", true))
    HS_PETSC(SNESSetConvergenceTest(snes_, converged, this, nullptr));
}

PetscErrorCode NewtonSolver::form_residual(SNES snes, Vec u, Vec R, void* ctx) {
  auto* self = static_cast<NewtonSolver*>(ctx);
  try {
    if (!self->problem_.residual(u, self->load_, R)) PetscCall(SNESSetFunctionDomainError(snes));
  } catch (const std::exception& e) {
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_LIB, "%s", e.what());
  }
  return 0;
}

PetscErrorCode NewtonSolver::form_jacobian(SNES snes, Vec u, Mat J, Mat, void* ctx) {
  auto* self = static_cast<NewtonSolver*>(ctx);
  try {
    if (!self->problem_.jacobian(u, self->load_, J)) PetscCall(SNESSetJacobianDomainError(snes));
    self->reset_if_pattern_grew();
  } catch (const std::exception& e) {
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_LIB, "%s", e.what());
  }
  return 0;
}

void NewtonSolver::reset_if_pattern_grew() {
  KSP ksp;
  HS_PETSC(SNESGetKSP(snes_, &ksp));
  problem_.reset_if_pattern_grew(ksp, pattern_version_);
}

PetscErrorCode NewtonSolver::form_objective(SNES, Vec u, PetscReal* energy, void* ctx) {
  auto* self = static_cast<NewtonSolver*>(ctx);
  try {
    double value = 0;
    // An inverted element has no energy: a value far above any reached makes the line search
    // shorten the step (it stops on an infinite one).
    *energy = self->problem_.potential_energy(u, self->load_, &value) ? value : 1e30;
  } catch (const std::exception& e) {
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_LIB, "%s", e.what());
  }
  return 0;
}

PetscErrorCode NewtonSolver::limit_step(SNESLineSearch, Vec u, Vec y, PetscBool* changed,
                                        void* ctx) {
  auto* self = static_cast<NewtonSolver*>(ctx);
  try {
    // SNES steps to u - lambda y.
    VecHandle du;
    PetscCall(VecDuplicate(y, du.out()));
    PetscCall(VecAXPBY(du, -1.0, 0.0, y));
    const double alpha = self->problem_.contact_step_limit(u, du, self->load_);
    if (alpha < 1) {
      PetscCall(VecScale(y, alpha));
      *changed = PETSC_TRUE;
    }
  } catch (const std::exception& e) {
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_LIB, "%s", e.what());
  }
  return 0;
}

PetscErrorCode NewtonSolver::limit_answer(SNESLineSearch, Vec u, Vec, Vec w, PetscBool*,
                                          PetscBool* changed_w, void* ctx) {
  auto* self = static_cast<NewtonSolver*>(ctx);
  try {
    VecHandle dw;
    PetscCall(VecDuplicate(w, dw.out()));
    PetscCall(VecWAXPY(dw, -1.0, u, w));
    const double alpha = self->problem_.contact_step_limit(u, dw, self->load_);
    if (alpha < 1) {
      PetscCall(VecWAXPY(w, alpha, dw, u));
      *changed_w = PETSC_TRUE;
    }
  } catch (const std::exception& e) {
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_LIB, "%s", e.what());
  }
  return 0;
}

PetscErrorCode NewtonSolver::converged(SNES snes, PetscInt it, PetscReal xnorm, PetscReal snorm,
                                       PetscReal fnorm, SNESConvergedReason* reason, void* ctx) {
  auto* self = static_cast<NewtonSolver*>(ctx);
  PetscCall(SNESConvergedDefault(snes, it, xnorm, snorm, fnorm, reason, nullptr));
  Vec u;
  PetscCall(SNESGetSolution(snes, &u));
  auto roundoff = [&](double* floor) -> PetscErrorCode {
    try {
      *floor = self->problem_.residual_roundoff(u);
    } catch (const std::exception& e) {
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_LIB, "%s", e.what());
    }
    return 0;
  };
  // The start's round-off floor: a step whose increment is small (a deep cutback) starts
  // near round-off, where no relative test passes and Newton wanders on the floor (self-contact
  // stalled so at 3e-13 against a floor of 1e-11). Without a load to scale the absolute
  // tolerance (a body moved by its Dirichlet values alone), a step may even start at its
  // solution to round-off (a rigid motion before contact, predicted exactly).
  if (it == 0) {
    self->first_norm_ = fnorm;
    self->roundoff_ = -1;
    PetscCall(roundoff(&self->start_floor_));
  }
  if (*reason != SNES_CONVERGED_ITERATING) return 0;
  const bool start_check = it == 0 && !self->atol_scaled_;
  const bool near = it > 0 && (fnorm <= 1e-6 * self->first_norm_ || fnorm <= self->start_floor_);
  if (!start_check && !near) return 0;
  double floor = self->start_floor_;
  if (it > 0) PetscCall(roundoff(&floor));
  PetscCall(PetscInfo(snes, "residual norm %g, its round-off %g\n", (double)fnorm, floor));
  if (fnorm <= floor) {
    *reason = SNES_CONVERGED_FNORM_ABS;
    self->roundoff_ = floor;
  }
  return 0;
}

void NewtonSolver::scale_absolute_tolerance(double load_norm) {
  if (options_.has("snes_atol") || load_norm <= 0) return;
  atol_scaled_ = true;
  HS_PETSC(SNESSetTolerances(snes_, 1e-9 * load_norm, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT,
                             PETSC_DEFAULT));
}

NewtonResult NewtonSolver::solve(Vec u, double s) {
  load_ = s;
  problem_.begin_solve();
  const NewtonResult r = solve_keeping_volumes(
      problem_, u, [&] { return solve_once(u); }, volume_monitor_);
  if (r.converged) problem_.accept_state(u, s);
  return r;
}

bool NewtonSolver::newton_step(Vec u, double s, Vec du, std::vector<double>& dmultipliers) {
  dmultipliers.clear();
  if (!problem_.residual(u, s, R_) || !problem_.jacobian(u, s, J_)) return false;
  reset_if_pattern_grew();
  KSP ksp;
  HS_PETSC(SNESGetKSP(snes_, &ksp));
  HS_PETSC(KSPSetOperators(ksp, J_, J_));
  {
    const OptionsScope scope(options_.database());  // MUMPS's factor, GAMG's levels
    HS_PETSC(KSPSolve(ksp, R_, du));
  }
  KSPConvergedReason reason;
  HS_PETSC(KSPGetConvergedReason(ksp, &reason));
  HS_PETSC(VecScale(du, -1.0));
  return reason > 0;
}

NewtonResult NewtonSolver::solve_once(Vec u) {
  // With obstacles, unless the deck or command line chose: a line search on the residual's
  // norm (l2) for static steps, where full Newton steps cycle on the barrier's and friction's
  // stiff convex energy (a sticking block: 227 iterations and 9 cutbacks against 62 and 3);
  // full steps for time steps, where l2's extrapolation beyond the step limit reached the
  // floor and failed a step that cannot be cut back (docs/contact.md).
  if (contact_search_) {
    SNESLineSearch search;
    HS_PETSC(SNESGetLineSearch(snes_, &search));
    HS_PETSC(SNESLineSearchSetType(
        search, problem_.has_inertia() ? SNESLINESEARCHBASIC : SNESLINESEARCHL2));
  }
  const auto& t = problem_.timers();
  const double assembly_before = t.residual_s + t.jacobian_s;
  const double t0 = MPI_Wtime();
  {
    const OptionsScope scope(options_.database());  // MUMPS's factor, GAMG's levels
    HS_PETSC(SNESSolve(snes_, nullptr, u));
  }
  const double assembly = t.residual_s + t.jacobian_s - assembly_before;
  solve_s_ += MPI_Wtime() - t0 - assembly;

  NewtonResult r;
  SNESConvergedReason reason;
  HS_PETSC(SNESGetConvergedReason(snes_, &reason));
  PetscInt its = 0, lits = 0;
  HS_PETSC(SNESGetIterationNumber(snes_, &its));
  HS_PETSC(SNESGetLinearSolveIterations(snes_, &lits));
  PetscReal norm = 0;
  HS_PETSC(SNESGetFunctionNorm(snes_, &norm));
  r.converged = reason > 0;
  r.iterations = static_cast<int>(its);
  r.linear_iterations = static_cast<int>(lits);
  r.residual_norm = norm;
  r.reason = roundoff_ >= 0 && reason > 0 ? "CONVERGED_ROUNDOFF" : SNESConvergedReasons[reason];
  // A law defined at every strain (small-strain elasticity) gives a solution even where it
  // turns a tetrahedron inside out: refused as the finite-strain laws' residual refuses it.
  if (r.converged && !problem_.orientation_preserved(u)) {
    r.converged = false;
    r.reason = "the solution inverts an element";
  }
  return r;
}

}  // namespace hs
