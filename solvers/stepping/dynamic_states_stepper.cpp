#include "solvers/stepping/dynamic_states_stepper.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/deck_reader.hpp"
#include "common/error.hpp"
#include "common/interrupt.hpp"
#include "deck/cavity_sections.hpp"
#include "solvers/stepping/states_stepper.hpp"

namespace hs {

DynamicStatesStepper::DynamicStatesStepper(const Config& config, Problem& problem,
                                           ConstraintSet& constraints, NonlinearSolver& solver,
                                           SteppingStats& stats, const ResultRecorder& recorder)
    : config_(config),
      problem_(problem),
      constraints_(constraints),
      solver_(solver),
      stats_(stats),
      recorder_(recorder),
      plans_(plan_states(config)),
      ends_(state_time_steps(config.states, config.time.dt)),
      nsteps_(static_cast<int>(std::ceil(config.time.end_time / config.time.dt - 1e-9))),
      integrator_(config, problem) {
  for (VecHandle* v :
       {&R_, &Mv_, &f_loads_, &f_loads_new_, &f_loads_start_, &u_old_, &u_start_, &scratch_, &g_})
    *v = VecHandle(problem.create_vector());
  const int m = constraints.size();
  work_.assign(m, 0.0);
  // The schedule's values at t = 0: the first state's, where its time is 0, else its start.
  plans_[0].begin(constraints_, config_.deck_path);
  const double tau = ends_[0] == 0 ? 1.0 : 0.0;
  plans_[0].set_targets(constraints_, tau);
  s_ = plans_[0].load_factor(tau);
  for (int c = 0; c < m; ++c) {
    lambda_.push_back(constraints[c].multiplier());
    measure_.push_back(constraints[c].measure());
  }
  stats.max_steps = max_substeps(nsteps_);
}

std::optional<StepReport> DynamicStatesStepper::initial_output() const {
  StepReport rest;
  rest.time = 0.0;
  rest.load_factor = s_;
  rest.output = true;
  return rest;
}

double DynamicStatesStepper::fraction_at(double n) const {
  const int64_t end = ends_[k_], begin = k_ == 0 ? 0 : ends_[k_ - 1];
  if (n >= static_cast<double>(end)) return 1.0;  // reached, and held after the last state
  return (n - static_cast<double>(begin)) / static_cast<double>(end - begin);
}

void DynamicStatesStepper::other_loads(Vec u, double s, Vec f) {
  problem_.external_load(u, s, f);
  for (int c = 0; c < constraints_.size(); ++c) {
    constraints_[c].forces(u, g_);
    HS_PETSC(VecAXPY(f, -constraints_[c].multiplier(), g_));
  }
  problem_.zero_constrained(f);
}

void DynamicStatesStepper::balance(Vec u) {
  problem_.internal_force(u, scratch_, &stored_);
  HS_PETSC(MatMult(integrator_.mass(), integrator_.velocity(), Mv_));
  HS_PETSC(VecDot(integrator_.velocity(), Mv_, &kinetic_));
  kinetic_ *= 0.5;
  double work = work_loads_;
  for (double w : work_) work += w;
  stats_.max_stored_energy = std::max(stats_.max_stored_energy, stored_);
  stats_.energy.push_back(kinetic_ + stored_ - work);
}

void DynamicStatesStepper::start(Vec u) {
  // Initial acceleration from M a0 = -(f_int(u0) - f_ext(u0)), the constraints' forces at the
  // schedule's t = 0 included.
  problem_.apply_dirichlet(u, s_);
  std::vector<double> control;
  constraints_.residual(u, s_, R_, control);
  integrator_.start(R_);
  other_loads(u, s_, f_loads_);
  for (int c = 0; c < constraints_.size(); ++c) measure_[c] = constraints_[c].measure();
  balance(u);
  started_ = true;
  // A first state at time 0 is reached at once: its entry is the rest configuration, written as
  // the run's first output step.
  if (ends_[0] == 0) {
    end_state(u, 0);
    states_.back()["step"] = 0;
    unnumbered_ = -1;
  }
}

void DynamicStatesStepper::end_state(Vec u, int n) {
  const StatePlan& plan = plans_[k_];
  if (plan.first)
    for (int c = 0; c < constraints_.size(); ++c) constraints_[c].mark_rest();
  states_.push_back(
      state_entry(config_, problem_, constraints_, u, plan.name, n * config_.time.dt, nullptr, s_));
  unnumbered_ = static_cast<int>(states_.size()) - 1;
}

void DynamicStatesStepper::number_output(int step) {
  if (unnumbered_ >= 0) states_[unnumbered_]["step"] = step;
  unnumbered_ = -1;
}

std::optional<StepReport> DynamicStatesStepper::advance(Vec u) {
  if (!started_) start(u);
  const double dt = config_.time.dt;
  const int n = n_ + 1;
  // The state this step ramps towards: the next one once the current one's time has passed.
  if (n > ends_[k_] && k_ + 1 < plans_.size()) {
    ++k_;
    plans_[k_].begin(constraints_, config_.deck_path);
  }
  const StatePlan& plan = plans_[k_];
  // A step whose solve fails is taken again from its start in 2, 4, ... equal sub-steps, the
  // schedule's values ramped over them, at most time.max_cutbacks halvings.
  HS_PETSC(VecCopy(u, u_start_));
  HS_PETSC(VecCopy(f_loads_, f_loads_start_));
  integrator_.save();
  const ConstraintSet::Point constraints_start = constraints_.point();
  const double s_start = s_, work_loads_start = work_loads_;
  const std::vector<double> work_start = work_, lambda_start = lambda_, measure_start = measure_;
  for (int halvings = 0;; ++halvings) {
    const std::string failure = take_substeps(u, n, 1 << halvings);
    if (failure.empty()) break;
    if (halvings == config_.time.max_cutbacks) {
      char where[200];
      std::snprintf(where, sizeof where, "time %s s, state '%s'", format_time(n * dt).c_str(),
                    plan.name.c_str());
      fail_step(problem_, n, where,
                failure + " after " + std::to_string(halvings) +
                    " halvings of the time step (time.max_cutbacks)");
    }
    ++stats_.cutbacks;
    HS_PETSC(VecCopy(u_start_, u));
    HS_PETSC(VecCopy(f_loads_start_, f_loads_));
    integrator_.restore();
    constraints_.return_to(constraints_start);
    s_ = s_start;
    work_loads_ = work_loads_start;
    work_ = work_start;
    lambda_ = lambda_start;
    measure_ = measure_start;
  }
  balance(u);
  n_ = n;
  StepReport step;
  step.index = n;
  step.time = n * dt;
  step.load_factor = s_;
  step.what = "time " + format_time(step.time) + " s, state " + plan.name;
  step.output = done() || (n % config_.output.every) == 0;
  if (n == ends_[k_]) {
    end_state(u, n);
    step.output = true;  // a state's end is an output step
  }
  return step;
}

std::string DynamicStatesStepper::take_substeps(Vec u, int n, int pieces) {
  const StatePlan& plan = plans_[k_];
  const double h = config_.time.dt / pieces;
  // Each solve: c M (u - u_pred) + f_int(u) - f_ext(u, lambda) = 0 with the constraints'
  // controls at its end (time_integrator.hpp).
  const TimeIntegrator::Scope inertia(integrator_);
  for (int k = 1; k <= pieces; ++k) {
    if (pieces > 1) stop_if_interrupted(problem_.comm());  // up to 2^max_cutbacks solves
    const double tau = fraction_at(n - 1 + static_cast<double>(k) / pieces);
    const double s = plan.load_factor(tau);
    plan.set_targets(constraints_, tau);
    HS_PETSC(VecCopy(u, u_old_));
    problem_.apply_dirichlet(u, s);
    if (constraints_.linearized()) constraints_.freeze_weights(u, s);
    integrator_.predict(u_old_, h);
    const NewtonResult r = solver_.solve(u, s);
    stats_.newton_iterations += r.iterations;
    stats_.linear_iterations += r.linear_iterations;
    if (!r.converged) return newton_failure(r) + plan.failure_note(constraints_);
    ++stats_.steps;
    s_ = s;
    integrator_.update(u, h);
    add_work(u, s);
  }
  return "";
}

void DynamicStatesStepper::add_work(Vec u, double s) {
  // By the trapezoidal rule: the loads' forces over du, the multipliers over dq. The solver's
  // last residual was at u: the constraints hold its values. u_old_: the solve's start.
  other_loads(u, s, f_loads_new_);
  HS_PETSC(VecAYPX(u_old_, -1.0, u));  // du
  double fdu_old = 0, fdu_new = 0;
  HS_PETSC(VecDot(f_loads_, u_old_, &fdu_old));
  HS_PETSC(VecDot(f_loads_new_, u_old_, &fdu_new));
  work_loads_ += 0.5 * (fdu_old + fdu_new);
  HS_PETSC(VecCopy(f_loads_new_, f_loads_));
  for (int c = 0; c < constraints_.size(); ++c) {
    const double lambda = constraints_[c].multiplier(), q = constraints_[c].measure();
    work_[c] += 0.5 * (lambda_[c] + lambda) * (q - measure_[c]);
    lambda_[c] = lambda;
    measure_[c] = q;
  }
}

void DynamicStatesStepper::add_history(HistorySources& sources) const {
  sources.time_column = "time_s";  // seconds, as a dynamic run's, not a state's fraction
  sources.columns.push_back([this](Vec, HistoryRow& row) {
    row.add("energy_J", stats_.energy.empty() ? 0.0 : stats_.energy.back());
    row.add("kinetic_energy_J", kinetic_);
    row.add("stored_energy_J", stored_);
    double work = work_loads_;
    for (double w : work_) work += w;
    row.add("work_J", work);
  });
}

void DynamicStatesStepper::add_summary(nlohmann::json& summary) const {
  summary["states"] = states_;
  summary["end_of_run"] = constraints_.report();
  nlohmann::json work = {{"loads", work_loads_}};
  for (int c = 0; c < constraints_.size(); ++c) work[constraints_[c].name()] = work_[c];
  summary["energy"]["work_J"] = work;
  summary["energy"]["kinetic_final"] = kinetic_;
  summary["energy"]["stored_final"] = stored_;
}

nlohmann::json DynamicStatesStepper::position() const {
  return {{"step", n_},
          {"time", n_ * config_.time.dt},
          {"dt", config_.time.dt},
          {"state", k_},
          {"ramps", plans_[k_].ramps_json(constraints_)},
          {"constraints", constraint_states(constraints_)},
          {"states", states_},
          {"work_loads", work_loads_},
          {"work", work_},
          {"last", done()}};
}

NamedVecs DynamicStatesStepper::checkpoint_fields(Vec u) const {
  return {{"displacement", u},
          {"velocity", integrator_.velocity()},
          {"acceleration", integrator_.acceleration()}};
}

void DynamicStatesStepper::resume(const Restart& restart, Vec u) {
  const nlohmann::json& p = restart.position();
  n_ = p.at("step");
  k_ = p.at("state");
  restart.read("displacement", problem_, u);
  restart.read("velocity", problem_, integrator_.velocity());
  restart.read("acceleration", problem_, integrator_.acceleration());
  restore_constraint_states(constraints_, p.at("constraints"));
  plans_[k_].resume_ramps(p.at("ramps"), constraints_);
  states_ = p.at("states");
  for (auto& state : states_) state["step"] = nullptr;  // in the earlier run's .h5
  work_loads_ = p.at("work_loads");
  work_ = p.at("work").get<std::vector<double>>();
  stats_.energy = restart.series("energy");
  // The loads at the step restarted from, as its residual left them.
  s_ = plans_[k_].load_factor(fraction_at(n_));
  std::vector<double> control;
  constraints_.residual(u, s_, R_, control);
  other_loads(u, s_, f_loads_);
  for (int c = 0; c < constraints_.size(); ++c) {
    lambda_[c] = constraints_[c].multiplier();
    measure_[c] = constraints_[c].measure();
  }
  problem_.internal_force(u, scratch_, &stored_);
  HS_PETSC(MatMult(integrator_.mass(), integrator_.velocity(), Mv_));
  HS_PETSC(VecDot(integrator_.velocity(), Mv_, &kinetic_));
  kinetic_ *= 0.5;
  started_ = true;
}

}  // namespace hs
