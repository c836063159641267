#include "solvers/stepping/states_stepper.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "common/error.hpp"
#include "solvers/stepping/load_model_error.hpp"
#include "solvers/tip_orientation.hpp"

namespace hs {

StatesStepper::StatesStepper(const Config& config, Problem& problem, ConstraintSet& constraints,
                             NonlinearSolver& solver, SteppingStats& stats,
                             const ResultRecorder& recorder)
    : config_(config),
      problem_(problem),
      constraints_(constraints),
      solver_(solver),
      stats_(stats),
      recorder_(recorder),
      plans_(plan_states(config)),
      predictor_(problem) {
  for (const StatePlan& plan : plans_) total_ += static_cast<int>(plan.taus.size());
  stats.max_steps = max_substeps(total_);
}

std::optional<StepReport> StatesStepper::advance(Vec u) {
  if (begun_ && i_ == plans_[k_].taus.size()) {  // the state ended with the last step
    end_state(u);
    ++k_;
    i_ = 0;
    begun_ = false;
    if (done()) return std::nullopt;
  }
  StatePlan& plan = plans_[k_];
  if (!begun_) {
    plan.begin(constraints_, config_.deck_path);
    plan.moves.begin(problem_);
    predictor_.start_path();
    begun_ = true;
  }
  const double tau = plan.taus[i_];
  solve_increment(u, tau);
  ++i_;
  StepReport step;
  step.index = ++done_;
  char what[160];
  std::snprintf(what, sizeof what, "state %s %.3g", plan.name.c_str(), tau);
  step.what = what;
  step.time = static_cast<double>(k_) + tau;
  step.load_factor = plan.load_factor(tau);
  step.output = i_ == plan.taus.size() || i_ % config_.output.every == 0;
  return step;
}

void StatesStepper::solve_increment(Vec u, double tau_to) {
  const StatePlan& plan = plans_[k_];
  VecHandle from(problem_.create_vector());
  auto attempt = [&](double tau) {
    HS_PETSC(VecCopy(u, from));
    std::vector<double> lambda = constraints_.multipliers();
    predictor_.predict(u, lambda, tau);
    constraints_.set_multipliers(lambda);
    const double s = plan.load_factor(tau);
    plan.set_targets(constraints_, tau);
    plan.moves.set(problem_, tau);
    problem_.apply_dirichlet(u, s);
    problem_.keep_outside_contact(from, u, s);
    if (constraints_.linearized()) constraints_.freeze_weights(u, s);
    const NewtonResult r = solver_.solve(u, s);
    if (r.converged) {
      predictor_.accept(tau);
    } else {
      predictor_.reject(u, lambda);
      constraints_.set_multipliers(lambda);
    }
    return r;
  };
  auto give_up = [&](double tau, const NewtonResult& r, const std::string& why) {
    std::ostringstream msg;
    msg << "state '" << plan.name << "' at " << tau << " of the way: " << why;
    // The element is named when inversion is the reason (a trial step that inverted one
    // and was halved does not make it the cause of a failure by iteration count).
    if (!r.converged && problem_.inverted_element() >= 0 &&
        r.reason.find("invert") != std::string::npos)
      msg << "; element " << problem_.inverted_element() << " is inverted (det F <= 0)";
    throw SolveError(msg.str() + plan.failure_note(constraints_));
  };
  advance_with_cutback(predictor_.parameter(), tau_to, config_.time.max_cutbacks, stats_,
                       problem_.comm(), attempt, give_up);
}

void StatesStepper::end_state(Vec u) {
  const StatePlan& plan = plans_[k_];
  if (plan.first)
    for (int c = 0; c < constraints_.size(); ++c) constraints_[c].mark_rest();
  // Its output step in this run's .h5 (null: written by the run restarted from).
  const nlohmann::json step =
      recorder_.written() > 0 ? nlohmann::json(recorder_.written() - 1) : nullptr;
  const double s = plan.load_factor(plan.taus.back());
  nlohmann::json entry = state_entry(config_, problem_, constraints_, u, plan.name,
                                     static_cast<double>(k_ + 1), step, s);
  // Not in a control deck: its states only bring it to its targets' start, its answers are
  // what it is run for, and an interactive session's first answer would wait for it.
  const auto error = config_.control ? std::nullopt
                                     : load_model_error(config_, problem_, constraints_, solver_, u,
                                                        s, plan.name, rest_change_);
  if (error) {
    entry["load_model_error"] = error->report;
    if (plan.first) rest_change_ = error->measure_change;
  }
  states_.push_back(std::move(entry));
}

nlohmann::json state_entry(const Config& config, Problem& problem, ConstraintSet& constraints,
                           Vec u, const std::string& name, double time, nlohmann::json step,
                           double load_factor) {
  nlohmann::json state;
  state["name"] = name;
  state["time"] = time;
  state["step"] = std::move(step);
  state["load_factor"] = load_factor;
  if (config.tip) {
    const TipOrientation t = tip_orientation(problem, config.tip->group, config.gravity, u);
    const auto& d = t.displacement;
    state["tip"] = {{"group", config.tip->group},
                    {"inclination_deg", t.inclination_deg},
                    {"rotation_deg", t.rotation_deg},
                    {"displacement_m", {d[0], d[1], d[2]}},
                    {"displacement_magnitude_m", std::hypot(d[0], d[1], d[2])}};
  }
  if (!problem.reaction_groups().empty())
    state["reactions_N"] = reactions_json(problem, u, load_factor);
  if (problem.has_contact()) state["contact"] = contact_json(problem, u, load_factor);
  state["added_volume_ml"] = constraints.added_volume() * 1e6;
  state["volume_change_ml"] = constraints.volume_change() * 1e6;
  const nlohmann::json actuators = constraints.report();
  state["cavities"] = actuators["cavities"];
  state["cables"] = actuators["cables"];
  return state;
}

nlohmann::json StatesStepper::position() const {
  const StatePlan& plan = plans_[k_];
  const nlohmann::json stepper = {
      {"ramps", plan.ramps_json(constraints_)},           {"tau", predictor_.parameter()},
      {"tau_last", predictor_.previous_parameter()},      {"has_last", predictor_.has_previous()},
      {"lambda_last", predictor_.previous_multipliers()}, {"rest_change", rest_change_}};
  return {{"state", k_},
          {"increment", i_},
          {"state_time", static_cast<double>(k_) + plan.taus[i_ - 1]},
          {"stepper", stepper},
          {"constraints", constraint_states(constraints_)},
          {"states", states_},
          {"last", i_ == plan.taus.size() && k_ + 1 == plans_.size()}};
}

NamedVecs StatesStepper::checkpoint_fields(Vec u) const {
  return {{"displacement", u}, {"previous_displacement", predictor_.previous()}};
}

void StatesStepper::resume(const Restart& restart, Vec u) {
  // The checkpoint's state k0, after its increment i0 (i0 = its size: at its end).
  const nlohmann::json& p = restart.position();
  const size_t k0 = p.at("state"), i0 = p.at("increment");
  if (k0 >= plans_.size() || i0 > plans_[k0].taus.size())
    throw InputError("--restart: the checkpoint's state " + std::to_string(k0) +
                     " is not one of this deck's");
  restart.read("displacement", problem_, u);
  restart.read("previous_displacement", problem_, predictor_.previous());
  restore_constraint_states(constraints_, p.at("constraints"));
  const nlohmann::json& stepper = p.at("stepper");
  plans_[k0].resume_ramps(stepper.at("ramps"), constraints_);
  predictor_.resume(stepper.at("tau"), stepper.at("tau_last"), stepper.at("has_last"),
                    stepper.at("lambda_last").get<std::vector<double>>());
  rest_change_ = stepper.value("rest_change", std::vector<double>{});
  states_ = p.at("states");
  for (auto& state : states_) state["step"] = nullptr;  // in the earlier run's .h5
  for (size_t k = 0; k < k0; ++k) done_ += static_cast<int>(plans_[k].taus.size());
  done_ += static_cast<int>(i0);
  k_ = k0;
  i_ = i0;
  begun_ = true;
}

void StatesStepper::add_summary(nlohmann::json& summary) const {
  summary["states"] = states_;
  summary["end_of_run"] = constraints_.report();
}

void StatesStepper::resume_done(nlohmann::json states) {
  states_ = std::move(states);
  for (auto& state : states_) state["step"] = nullptr;  // in the earlier run's .h5
  k_ = plans_.size();
}

}  // namespace hs
