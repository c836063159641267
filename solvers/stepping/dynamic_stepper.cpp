#include "solvers/stepping/dynamic_stepper.hpp"

#include <petscksp.h>

#include <algorithm>
#include <cmath>

#include "common/deck_reader.hpp"
#include "solvers/solver_options.hpp"

namespace hs {

DynamicStepper::DynamicStepper(const Config& config, Problem& problem, NonlinearSolver& solver,
                               SteppingStats& stats)
    : config_(config),
      problem_(problem),
      solver_(solver),
      stats_(stats),
      nsteps_(static_cast<int>(std::ceil(config.time.end_time / config.time.dt - 1e-9))) {
  {
    // The mass matrix reads the mass solve's options (a matrix's -mat_view, as the tangent reads
    // its solver's), not PETSc's global database.
    const SolverOptions options(kMassPrefix, config.solver, {},
                                SolverOptions::Reach::own_prefix_only);
    const OptionsScope scope(options.database());
    inertia_.M = MatHandle(problem.create_mass_matrix());
  }
  for (VecHandle* v : {&v_, &a_, &a_new_, &R_, &inertia_.u_pred, &Mv_, &f_ext_, &scratch_})
    *v = VecHandle(problem.create_vector());  // zeroed: v(0) = 0
}

std::optional<StepReport> DynamicStepper::initial_output() const {
  StepReport rest;
  rest.time = 0.0;
  rest.output = true;
  return rest;
}

// E = 1/2 v.M v + int psi - f_ext.u (f_ext at full load on the current configuration).
double DynamicStepper::total_energy(Vec u) {
  double stored = 0, kinetic = 0, work = 0;
  problem_.internal_force(u, scratch_, &stored);
  HS_PETSC(MatMult(inertia_.M, v_, Mv_));
  HS_PETSC(VecDot(v_, Mv_, &kinetic));
  problem_.external_load(u, 1.0, f_ext_);
  HS_PETSC(VecDot(f_ext_, u, &work));
  stats_.max_stored_energy = std::max(stats_.max_stored_energy, stored);
  return 0.5 * kinetic + stored - work;
}

void DynamicStepper::start(Vec u) {
  // Initial acceleration from M a0 = -(f_int(u0) - f_ext): CG on the mass matrix.
  problem_.apply_dirichlet(u, 1.0);
  problem_.residual(u, 1.0, R_);
  // Its solver is set here: no preset, and only the options with its prefix (hs_mass_).
  const SolverOptions options(kMassPrefix, config_.solver, {},
                              SolverOptions::Reach::own_prefix_only);
  KspHandle mass_solver;
  HS_PETSC(KSPCreate(problem_.comm(), mass_solver.out()));
  options.attach(reinterpret_cast<PetscObject>(mass_solver.get()));
  HS_PETSC(KSPSetOptionsPrefix(mass_solver, kMassPrefix));
  HS_PETSC(KSPSetOperators(mass_solver, inertia_.M, inertia_.M));
  HS_PETSC(KSPSetType(mass_solver, KSPCG));
  PC pc;
  HS_PETSC(KSPGetPC(mass_solver, &pc));
  HS_PETSC(PCSetType(pc, PCJACOBI));
  HS_PETSC(KSPSetTolerances(mass_solver, 1e-12, 1e-30, PETSC_DEFAULT, 1000));
  const OptionsScope scope(options.database());
  HS_PETSC(KSPSetFromOptions(mass_solver));
  HS_PETSC(KSPSolve(mass_solver, R_, a_));
  HS_PETSC(VecScale(a_, -1.0));
  stats_.energy.push_back(total_energy(u));
  started_ = true;
}

std::optional<StepReport> DynamicStepper::advance(Vec u) {
  if (!started_) start(u);
  const TimeConfig& time = config_.time;
  const bool newmark = time.integrator == Integrator::newmark;
  const double dt = time.dt, beta = time.newmark_beta, gamma = time.newmark_gamma;
  const int n = n_ + 1;
  // The problem carries the inertia during the step's solve only, and lets go of it on every
  // way out (a failed step leaves by an exception).
  struct Inertia {
    Problem& problem;
    Inertia(Problem& p, const InertiaTerm* term) : problem(p) { problem.set_inertia(term); }
    ~Inertia() { problem.set_inertia(nullptr); }
  } inertia(problem_, &inertia_);
  // u_pred = u + dt v + dt^2 (1/2 - beta) a  (Newmark), u + dt v (backward Euler);
  // the step solves c M (u - u_pred) + f_int(u) - f_ext = 0, c = 1/(beta dt^2) or 1/dt^2.
  HS_PETSC(VecWAXPY(inertia_.u_pred, dt, v_, u));
  if (newmark) HS_PETSC(VecAXPY(inertia_.u_pred, dt * dt * (0.5 - beta), a_));
  inertia_.c = newmark ? 1 / (beta * dt * dt) : 1 / (dt * dt);
  const NewtonResult r = solver_.solve(u, 1.0);
  stats_.newton_iterations += r.iterations;
  stats_.linear_iterations += r.linear_iterations;
  if (!r.converged) fail_step(problem_, n, "time " + std::to_string(n * dt), newton_failure(r));
  ++stats_.steps;
  // a_new = c (u - u_pred); v += dt ((1 - gamma) a + gamma a_new) or dt a_new.
  HS_PETSC(VecWAXPY(a_new_, -1.0, inertia_.u_pred, u));
  HS_PETSC(VecScale(a_new_, inertia_.c));
  if (newmark) {
    HS_PETSC(VecAXPY(v_, dt * (1 - gamma), a_));
    HS_PETSC(VecAXPY(v_, dt * gamma, a_new_));
  } else {
    HS_PETSC(VecAXPY(v_, dt, a_new_));
  }
  HS_PETSC(VecCopy(a_new_, a_));
  stats_.energy.push_back(total_energy(u));
  n_ = n;
  StepReport step;
  step.index = n;
  step.time = n * dt;
  step.what = "time " + format_number(step.time) + " s";
  step.output = done() || (n % config_.output.every) == 0;
  return step;
}

nlohmann::json DynamicStepper::position() const {
  return {{"step", n_}, {"time", n_ * config_.time.dt}, {"dt", config_.time.dt}, {"last", done()}};
}

NamedVecs DynamicStepper::checkpoint_fields(Vec u) const {
  return {{"displacement", u}, {"velocity", v_}, {"acceleration", a_}};
}

void DynamicStepper::resume(const Restart& restart, Vec u) {
  n_ = restart.position().at("step");
  restart.read("displacement", problem_, u);
  restart.read("velocity", problem_, v_);
  restart.read("acceleration", problem_, a_);
  stats_.energy = restart.series("energy");
  started_ = true;
}

}  // namespace hs
