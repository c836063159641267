#include "solvers/newton_solver.hpp"

#include <map>

#include "common/error.hpp"

namespace hs {
namespace {

void set_default(const std::string& name, const std::string& value) {
  PetscBool set = PETSC_FALSE;
  HS_PETSC(PetscOptionsHasName(nullptr, nullptr, ("-" + name).c_str(), &set));
  if (!set) HS_PETSC(PetscOptionsSetValue(nullptr, ("-" + name).c_str(), value.c_str()));
}

// Whether `type` is a registered type of the object kind that option `name` sets (by its
// suffix); true for options of other kinds, which PETSc checks when they are used.
bool known_type(const std::string& name, const std::string& type) {
  auto ends_with = [&](const std::string& suffix) {
    return name.size() >= suffix.size() &&
           name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
  };
  // Errors come back as codes, without PETSc's printed trace.
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  PetscErrorCode error = 0;
  if (ends_with("linesearch_type")) {
    LineSearchHandle ls;
    SNESLineSearchCreate(PETSC_COMM_SELF, ls.out());
    error = SNESLineSearchSetType(ls, type.c_str());
  } else if (ends_with("snes_type")) {
    SnesHandle snes;
    SNESCreate(PETSC_COMM_SELF, snes.out());
    error = SNESSetType(snes, type.c_str());
  } else if (ends_with("ksp_type")) {
    KspHandle ksp;
    KSPCreate(PETSC_COMM_SELF, ksp.out());
    error = KSPSetType(ksp, type.c_str());
  } else if (ends_with("pc_type")) {
    PcHandle pc;
    PCCreate(PETSC_COMM_SELF, pc.out());
    error = PCSetType(pc, type.c_str());
  }  // each object is released in its branch, still under the return handler
  PetscPopErrorHandler();
  return error == 0;
}

}  // namespace

void check_solver_types(const SolverConfig& solver, const std::string& deck_path) {
  for (const auto& [name, value] : solver.petsc_options)
    if (!known_type(name, value))
      throw InputError(deck_path + ": solver.petsc_options." + name + ": unknown PETSc type '" +
                       value + "'");
  for (const char* name : {"snes_type", "snes_linesearch_type", "ksp_type", "pc_type",
                           "mg_levels_ksp_type", "mg_levels_pc_type"}) {
    char value[256];
    PetscBool set = PETSC_FALSE;
    HS_PETSC(PetscOptionsGetString(nullptr, nullptr, (std::string("-") + name).c_str(), value,
                                   sizeof value, &set));
    if (set && !known_type(name, value))
      throw InputError(std::string("command line: -") + name + ": unknown PETSc type '" + value +
                       "'");
  }
}

void set_solver_options(const SolverConfig& solver, bool symmetric_tangent, bool definite_tangent) {
  // The deck's options first, so that they win over the preset; the command line, already
  // in the database, wins over both.
  for (const auto& [name, value] : solver.petsc_options) set_default(name, value);

  // Convergence is judged on the residual (never on a small step alone: a stalled
  // iterative solve would otherwise look converged). No divergence tolerance: a full Newton
  // step from rest can raise the residual by more than PETSc's default factor 1e4 before it
  // converges (the 1M-dof cantilever: x1.2e4 after its first step, then 5 more to 1e-8,
  // where the default stopped it and cost a cutback and 6 iterations); a step that truly
  // diverges is stopped by snes_max_it, an inverted element or a non-finite residual, and cut
  // back.
  const std::map<std::string, std::string> common = {
      {"snes_type", "newtonls"}, {"snes_linesearch_type", "basic"},   {"snes_rtol", "1e-8"},
      {"snes_stol", "0"},        {"snes_divergence_tolerance", "-1"}, {"snes_max_it", "30"}};
  for (const auto& [k, v] : common) set_default(k, v);
  switch (solver.preset) {
    case SolverPreset::mumps:
      set_default("ksp_type", "preonly");
      // A symmetric tangent is factored as L D L^T (MUMPS's general symmetric mode, with
      // pivoting, so an indefinite tangent near a limit point is fine): ~30% less time than LU.
      set_default("pc_type", symmetric_tangent ? "cholesky" : "lu");
      set_default("pc_factor_mat_solver_type", "mumps");
      break;
    case SolverPreset::gamg:
      // MINRES for a symmetric tangent that may be indefinite (GAMG's smoothers keep the
      // preconditioner definite): a finite-strain Newton iterate past the solution meets one,
      // and CG stopping there cost a load-step cutback.
      set_default("ksp_type", !symmetric_tangent ? "gmres" : definite_tangent ? "cg" : "minres");
      set_default("pc_type", "gamg");
      set_default("ksp_rtol", "1e-10");
      set_default("ksp_max_it", "2000");
      set_default("pc_gamg_threshold", "0.01");
      set_default("mg_levels_ksp_type", "chebyshev");
      set_default("mg_levels_pc_type", "jacobi");
      break;
  }
}

NewtonSolver::NewtonSolver(Problem& problem) : problem_(problem) {
  J_ = MatHandle(problem.create_matrix());
  R_ = VecHandle(problem.create_vector());
  PetscBool near_null = PETSC_TRUE;
  HS_PETSC(PetscOptionsGetBool(nullptr, nullptr, "-hs_near_null_space", &near_null, nullptr));
  if (!near_null) HS_PETSC(MatSetNearNullSpace(J_, nullptr));
  HS_PETSC(SNESCreate(problem.comm(), snes_.out()));
  HS_PETSC(SNESSetFunction(snes_, R_, form_residual, this));
  HS_PETSC(SNESSetJacobian(snes_, J_, J_, form_jacobian, this));
  if (problem.has_potential()) HS_PETSC(SNESSetObjective(snes_, form_objective, this));
  HS_PETSC(SNESSetFromOptions(snes_));
  PetscBool roundoff = PETSC_TRUE;  // -hs_newton_roundoff false: PETSc's test alone
  HS_PETSC(PetscOptionsGetBool(nullptr, nullptr, "-hs_newton_roundoff", &roundoff, nullptr));
  if (roundoff) HS_PETSC(SNESSetConvergenceTest(snes_, converged, this, nullptr));
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
  } catch (const std::exception& e) {
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_LIB, "%s", e.what());
  }
  return 0;
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

PetscErrorCode NewtonSolver::converged(SNES snes, PetscInt it, PetscReal xnorm, PetscReal snorm,
                                       PetscReal fnorm, SNESConvergedReason* reason, void* ctx) {
  auto* self = static_cast<NewtonSolver*>(ctx);
  PetscCall(SNESConvergedDefault(snes, it, xnorm, snorm, fnorm, reason, nullptr));
  if (it == 0) {
    self->first_norm_ = fnorm;
    self->roundoff_ = -1;
  }
  if (*reason != SNES_CONVERGED_ITERATING || it == 0 || !(fnorm <= 1e-6 * self->first_norm_))
    return 0;
  Vec u;
  PetscCall(SNESGetSolution(snes, &u));
  double floor = 0;
  try {
    floor = self->problem_.residual_roundoff(u);
  } catch (const std::exception& e) {
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_LIB, "%s", e.what());
  }
  PetscCall(PetscInfo(snes, "residual norm %g, its round-off %g\n", (double)fnorm, floor));
  if (fnorm <= floor) {
    *reason = SNES_CONVERGED_FNORM_ABS;
    self->roundoff_ = floor;
  }
  return 0;
}

void NewtonSolver::scale_absolute_tolerance(double load_norm) {
  PetscBool set = PETSC_FALSE;
  HS_PETSC(PetscOptionsHasName(nullptr, nullptr, "-snes_atol", &set));
  if (set || load_norm <= 0) return;
  HS_PETSC(SNESSetTolerances(snes_, 1e-9 * load_norm, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT,
                             PETSC_DEFAULT));
}

NewtonResult NewtonSolver::solve(Vec u, double s) {
  load_ = s;
  const auto& t = problem_.timers();
  const double assembly_before = t.residual_s + t.jacobian_s;
  const double t0 = MPI_Wtime();
  HS_PETSC(SNESSolve(snes_, nullptr, u));
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
