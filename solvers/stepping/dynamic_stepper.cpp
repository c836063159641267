#include "solvers/stepping/dynamic_stepper.hpp"

#include <algorithm>
#include <cmath>

#include "common/deck_reader.hpp"
#include "common/interrupt.hpp"

namespace hs {

DynamicStepper::DynamicStepper(const Config& config, Problem& problem, NonlinearSolver& solver,
                               SteppingStats& stats)
    : config_(config),
      problem_(problem),
      solver_(solver),
      stats_(stats),
      nsteps_(static_cast<int>(std::ceil(config.time.end_time / config.time.dt - 1e-9))),
      integrator_(config, problem) {
  for (VecHandle* v : {&R_, &Mv_, &f_ext_, &scratch_, &u_start_})
    *v = VecHandle(problem.create_vector());
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
  HS_PETSC(MatMult(integrator_.mass(), integrator_.velocity(), Mv_));
  HS_PETSC(VecDot(integrator_.velocity(), Mv_, &kinetic));
  problem_.external_load(u, 1.0, f_ext_);
  HS_PETSC(VecDot(f_ext_, u, &work));
  stats_.max_stored_energy = std::max(stats_.max_stored_energy, stored);
  return 0.5 * kinetic + stored - work;
}

void DynamicStepper::start(Vec u) {
  // Initial acceleration from M a0 = -(f_int(u0) - f_ext): CG on the mass matrix.
  problem_.apply_dirichlet(u, 1.0);
  problem_.residual(u, 1.0, R_);
  integrator_.start(R_);
  stats_.energy.push_back(total_energy(u));
  started_ = true;
}

std::optional<StepReport> DynamicStepper::advance(Vec u) {
  if (!started_) start(u);
  const double dt = config_.time.dt;
  const int n = n_ + 1;
  HS_PETSC(VecCopy(u, u_start_));
  integrator_.save();
  // A step whose solve fails is taken again from its start in 2, 4, ... equal sub-steps, at
  // most time.max_cutbacks halvings: the shorter step's inertia term stiffens the tangent
  // (c = 1 / (beta h^2)) and its predictor starts nearer the solution.
  for (int halvings = 0;; ++halvings) {
    const std::string failure = take_substeps(u, dt, 1 << halvings);
    if (failure.empty()) break;
    if (halvings == config_.time.max_cutbacks)
      fail_step(problem_, n, "time " + format_time(n * dt) + " s",
                failure + " after " + std::to_string(halvings) +
                    " halvings of the time step (time.max_cutbacks)");
    ++stats_.cutbacks;
    HS_PETSC(VecCopy(u_start_, u));
    integrator_.restore();
  }
  stats_.energy.push_back(total_energy(u));
  n_ = n;
  StepReport step;
  step.index = n;
  step.time = n * dt;
  step.what = "time " + format_time(step.time) + " s";
  step.output = done() || (n % config_.output.every) == 0;
  return step;
}

std::string DynamicStepper::take_substeps(Vec u, double dt, int pieces) {
  const double h = dt / pieces;
  const TimeIntegrator::Scope inertia(integrator_);
  for (int k = 0; k < pieces; ++k) {
    if (pieces > 1) stop_if_interrupted(problem_.comm());  // up to 2^max_cutbacks solves
    integrator_.predict(u, h);
    const NewtonResult r = solver_.solve(u, 1.0);
    stats_.newton_iterations += r.iterations;
    stats_.linear_iterations += r.linear_iterations;
    if (!r.converged) return newton_failure(r);
    ++stats_.steps;
    integrator_.update(u, h);
  }
  return "";
}

nlohmann::json DynamicStepper::position() const {
  return {{"step", n_}, {"time", n_ * config_.time.dt}, {"dt", config_.time.dt}, {"last", done()}};
}

NamedVecs DynamicStepper::checkpoint_fields(Vec u) const {
  return {{"displacement", u},
          {"velocity", integrator_.velocity()},
          {"acceleration", integrator_.acceleration()}};
}

void DynamicStepper::resume(const Restart& restart, Vec u) {
  n_ = restart.position().at("step");
  restart.read("displacement", problem_, u);
  restart.read("velocity", problem_, integrator_.velocity());
  restart.read("acceleration", problem_, integrator_.acceleration());
  stats_.energy = restart.series("energy");
  started_ = true;
}

}  // namespace hs
