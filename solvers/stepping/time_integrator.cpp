#include "solvers/stepping/time_integrator.hpp"

#include <petscksp.h>

#include "solvers/petsc_check.hpp"
#include "solvers/solver_options.hpp"

namespace hs {

TimeIntegrator::TimeIntegrator(const Config& config, Problem& problem)
    : config_(config), problem_(problem) {
  {
    const SolverOptions options(kMassPrefix, config.solver, {},
                                SolverOptions::Reach::own_prefix_only);
    const OptionsScope scope(options.database());
    inertia_.M = MatHandle(problem.create_mass_matrix());
  }
  for (VecHandle* v : {&v_, &a_, &a_new_, &v_saved_, &a_saved_, &inertia_.u_pred})
    *v = VecHandle(problem.create_vector());  // zeroed: v(0) = 0
}

void TimeIntegrator::start(Vec R) {
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
  HS_PETSC(KSPSolve(mass_solver, R, a_));
  HS_PETSC(VecScale(a_, -1.0));
}

void TimeIntegrator::predict(Vec u, double dt) {
  const TimeConfig& time = config_.time;
  const bool newmark = time.integrator == Integrator::newmark;
  const double beta = time.newmark_beta;
  HS_PETSC(VecWAXPY(inertia_.u_pred, dt, v_, u));
  if (newmark) HS_PETSC(VecAXPY(inertia_.u_pred, dt * dt * (0.5 - beta), a_));
  inertia_.c = newmark ? 1 / (beta * dt * dt) : 1 / (dt * dt);
}

void TimeIntegrator::update(Vec u, double dt) {
  const TimeConfig& time = config_.time;
  const double gamma = time.newmark_gamma;
  HS_PETSC(VecWAXPY(a_new_, -1.0, inertia_.u_pred, u));
  HS_PETSC(VecScale(a_new_, inertia_.c));
  if (time.integrator == Integrator::newmark) {
    HS_PETSC(VecAXPY(v_, dt * (1 - gamma), a_));
    HS_PETSC(VecAXPY(v_, dt * gamma, a_new_));
  } else {
    HS_PETSC(VecAXPY(v_, dt, a_new_));
  }
  HS_PETSC(VecCopy(a_new_, a_));
}

void TimeIntegrator::save() {
  HS_PETSC(VecCopy(v_, v_saved_));
  HS_PETSC(VecCopy(a_, a_saved_));
}

void TimeIntegrator::restore() {
  HS_PETSC(VecCopy(v_saved_, v_));
  HS_PETSC(VecCopy(a_saved_, a_));
}

}  // namespace hs
