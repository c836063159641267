#include "solvers/state_stepping.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "common/error.hpp"
#include "common/interrupt.hpp"
#include "solvers/progress.hpp"

namespace hs {
namespace {

constexpr double kPi = 3.14159265358979323846;

// One state: its increments' end points tau (fractions of the state) and what tau sets.
struct StatePlan {
  std::string name;
  std::vector<double> taus;
  bool first = false;
  // Later states: per cavity, the control to ramp (from -> to); unnamed cavities keep theirs.
  struct Ramp {
    bool active = false;
    Constraint::Control control = Constraint::Control::multiplier;
    double from = 0, to = 0;
  };
  std::vector<Ramp> ramps;
};

std::vector<StatePlan> plan_states(const Config& config) {
  std::vector<StateConfig> states = config.states;
  if (states.empty()) {
    StateConfig only;
    only.name = "final";
    only.steps = config.time.steps;
    states.push_back(only);
  }
  std::vector<StatePlan> plans;
  for (size_t k = 0; k < states.size(); ++k) {
    StatePlan p;
    p.name = states[k].name;
    p.first = k == 0;
    if (p.first && config.states.empty() && !config.time.schedule.empty()) {
      p.taus = config.time.schedule;
    } else {
      for (int i = 1; i <= states[k].steps; ++i)
        p.taus.push_back(static_cast<double>(i) / states[k].steps);
    }
    // One ramp per constraint of the ConstraintSet: the cavities, then the cables (which the
    // states do not ramp: they keep their first-state tension).
    p.ramps.resize(config.cavities.size() + config.cables.size());
    for (size_t c = 0; c < config.cavities.size(); ++c) {
      auto it = states[k].cavities.find(config.cavities[c].group);
      if (it == states[k].cavities.end()) continue;
      p.ramps[c].active = true;
      p.ramps[c].control =
          it->second.pressure ? Constraint::Control::multiplier : Constraint::Control::measure;
      p.ramps[c].to = it->second.pressure ? *it->second.pressure : *it->second.added_volume;
    }
    plans.push_back(p);
  }
  return plans;
}

class StateStepper {
 public:
  StateStepper(const Config& config, Problem& problem, ConstraintSet& constraints,
               BorderedNewton& newton, SteppingStats& stats)
      : config_(config),
        problem_(problem),
        constraints_(constraints),
        newton_(newton),
        stats_(stats) {
    u_last_ = VecHandle(problem.create_vector());
    saved_ = VecHandle(problem.create_vector());
  }

  // Starts a state: fixes its ramps' start values from the current state of the cavities.
  void begin(StatePlan& plan) {
    plan_ = &plan;
    tau_ = 0;
    has_last_ = false;
    for (int c = 0; c < constraints_.size(); ++c) {
      auto& ramp = plan.ramps[c];
      if (!ramp.active) continue;
      Constraint& cav = constraints_[c];
      if (ramp.control == Constraint::Control::multiplier) {
        ramp.from = cav.lambda;
      } else {
        ramp.from = cav.measure;
        const double added = ramp.to;
        ramp.to += cav.rest_measure;  // added volume is counted from the end of the first state
        // Walls cannot pass through each other (no contact): a volume <= 0 has no solution.
        if (!(ramp.to > 0)) {
          std::ostringstream msg;
          msg << config_.deck_path << ": state '" << plan.name << "': cavity '" << cav.name()
              << "': added_volume " << added << " m^3 would leave it a volume of " << ramp.to
              << " m^3 (it holds " << cav.rest_measure
              << " m^3 at the end of the first state); a cavity's volume must stay > 0";
          throw InputError(msg.str());
        }
      }
      cav.control = ramp.control;
    }
  }

  double load_factor(double tau) const { return plan_->first ? tau : 1.0; }

  // For a checkpoint: the ramps of the current state and the predictor's memory (u_last()
  // is the vector). resume() puts them back in place of begin().
  nlohmann::json position() const {
    nlohmann::json ramps = nlohmann::json::array();
    for (const auto& r : plan_->ramps)
      ramps.push_back({{"active", r.active},
                       {"control", static_cast<int>(r.control)},
                       {"from", r.from},
                       {"to", r.to}});
    return {{"ramps", ramps},
            {"tau", tau_},
            {"tau_last", tau_last_},
            {"has_last", has_last_},
            {"lambda_last", lambda_last_}};
  }
  Vec u_last() const { return u_last_; }
  void resume(StatePlan& plan, const nlohmann::json& p) {
    plan_ = &plan;
    for (size_t c = 0; c < plan.ramps.size(); ++c) {
      const auto& r = p.at("ramps").at(c);
      plan.ramps[c].active = r.at("active");
      plan.ramps[c].control = static_cast<Constraint::Control>(r.at("control").get<int>());
      plan.ramps[c].from = r.at("from");
      plan.ramps[c].to = r.at("to");
    }
    tau_ = p.at("tau");
    tau_last_ = p.at("tau_last");
    has_last_ = p.at("has_last");
    lambda_last_ = p.at("lambda_last").get<std::vector<double>>();
  }

  // Sets the cavity targets at tau.
  void set_targets(double tau) {
    for (int c = 0; c < constraints_.size(); ++c) {
      Constraint& cav = constraints_[c];
      const auto& ramp = plan_->ramps[c];
      if (ramp.active) {
        cav.target = ramp.from + tau * (ramp.to - ramp.from);
      } else if (plan_->first) {
        if (cav.control == Constraint::Control::multiplier)
          cav.target = tau * cav.first_state_multiplier;
        if (cav.control == Constraint::Control::measure)
          cav.target = cav.reference_measure + tau * cav.first_state_measure_change.value_or(0.0);
      }
      if (cav.control == Constraint::Control::multiplier) cav.lambda = cav.target;
    }
  }

  // Advances the current state to tau_to, halving failed increments.
  void advance(Vec u, double tau_to) {
    auto attempt = [&](double tau) {
      const std::vector<double> lambda = constraints_.multipliers();
      HS_PETSC(VecCopy(u, saved_));
      predict(u, tau);
      const double s = load_factor(tau);
      set_targets(tau);
      problem_.apply_dirichlet(u, s);
      if (constraints_.linearized()) constraints_.freeze_weights(u, s);
      const NewtonResult r = newton_.solve(u, s);
      if (r.converged) {
        HS_PETSC(VecCopy(saved_, u_last_));
        lambda_last_ = lambda;
        tau_last_ = tau_;
        tau_ = tau;
        has_last_ = true;
      } else {
        HS_PETSC(VecCopy(saved_, u));
        constraints_.set_multipliers(lambda);
      }
      return r;
    };
    auto give_up = [&](double tau, const NewtonResult& r, const std::string& why) {
      std::ostringstream msg;
      msg << "state '" << plan_->name << "' at " << tau << " of the way: " << why;
      // The element is named when inversion is the reason (a trial step that inverted one
      // and was halved does not make it the cause of a failure by iteration count).
      if (!r.converged && problem_.inverted_element() >= 0 &&
          r.reason.find("invert") != std::string::npos)
        msg << "; element " << problem_.inverted_element() << " is inverted (det F <= 0)";
      // A pressure ramped past the cavity's pressure extremum (the peak of an inflation, the
      // buckling of walls under suction) has no equilibrium nearby.
      for (int c = 0; c < constraints_.size(); ++c) {
        const Constraint& cav = constraints_[c];
        const bool ramped =
            plan_->ramps[c].active || (plan_->first && cav.first_state_multiplier != 0);
        if (ramped && cav.is_cavity() && cav.control == Constraint::Control::multiplier &&
            cav.target != 0)
          msg << "; cavity '" << cav.name() << "' was at " << cav.target
              << " Pa on a pressure ramp (past a pressure peak or a buckling of the walls there "
                 "is no equilibrium under pressure control: prescribe added_volume to pass it)";
      }
      throw SolveError(msg.str());
    };
    advance_with_cutback(tau_, tau_to, config_.time.max_cutbacks, stats_, problem_.comm(), attempt,
                         give_up);
  }

 private:
  // Secant predictor from the last two converged points of this state (u and pressures).
  void predict(Vec u, double tau) {
    if (!has_last_ || tau_ == tau_last_) return;
    const double k = (tau - tau_) / (tau_ - tau_last_);
    HS_PETSC(VecAXPBY(u, -k, 1 + k, u_last_));
    std::vector<double> lambda = constraints_.multipliers();
    for (size_t c = 0; c < lambda.size(); ++c)
      lambda[c] = (1 + k) * lambda[c] - k * lambda_last_[c];
    constraints_.set_multipliers(lambda);
  }

  const Config& config_;
  Problem& problem_;
  ConstraintSet& constraints_;
  BorderedNewton& newton_;
  SteppingStats& stats_;
  StatePlan* plan_ = nullptr;
  double tau_ = 0, tau_last_ = 0;
  bool has_last_ = false;
  std::vector<double> lambda_last_;
  VecHandle u_last_, saved_;
};

}  // namespace

namespace {

double angle_deg(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  const double cross =
      std::hypot(a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]);
  return std::atan2(cross, a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) * 180 / kPi;
}

}  // namespace

TipOrientation tip_orientation(Problem& problem, const std::string& group,
                               const std::array<double, 3>& gravity, Vec u) {
  TipOrientation t;
  const auto n = problem.area_vector(group, u);
  VecHandle zero;
  HS_PETSC(VecDuplicate(u, zero.out()));
  HS_PETSC(VecZeroEntries(zero));
  const auto n0 = problem.area_vector(group, zero);
  t.rotation_deg = angle_deg(n0, n);
  // The angle to gravity is 90 deg minus the inclination below the plane normal to it.
  if (std::hypot(gravity[0], gravity[1], gravity[2]) > 0 && std::hypot(n[0], n[1], n[2]) > 0)
    t.inclination_deg = 90 - angle_deg(n, gravity);
  return t;
}

StateRun run_states(const Config& config, Problem& problem, ConstraintSet& constraints,
                    BorderedNewton& newton, ResultRecorder& recorder, Vec u, SteppingStats& stats,
                    MPI_Comm comm, Checkpointer& checkpoints, const Restart* restart) {
  StateRun run;
  std::vector<StatePlan> plans = plan_states(config);
  StateStepper stepper(config, problem, constraints, newton, stats);
  int total = 0, done = 0;
  for (const StatePlan& plan : plans) total += static_cast<int>(plan.taus.size());
  // A restart continues state k0 after its increment i0 (i0 = its size: at its end).
  size_t k0 = 0, i0 = 0;
  if (restart) {
    const nlohmann::json& p = restart->position();
    k0 = p.at("state");
    i0 = p.at("increment");
    if (k0 >= plans.size() || i0 > plans[k0].taus.size())
      throw InputError("--restart: the checkpoint's state " + std::to_string(k0) +
                       " is not one of this deck's");
    restart->read("displacement", problem, u);
    restart->read("previous_displacement", problem, stepper.u_last());
    restore_constraint_states(constraints, p.at("constraints"));
    stepper.resume(plans[k0], p.at("stepper"));
    run.states = p.at("states");
    for (auto& state : run.states) state["step"] = nullptr;  // in the earlier run's .h5
    for (size_t k = 0; k < k0; ++k) done += static_cast<int>(plans[k].taus.size());
    done += static_cast<int>(i0);
  }
  stats.max_steps = max_substeps(total);
  Progress progress(config.output.progress, comm, total);
  for (size_t k = k0; k < plans.size(); ++k) {
    StatePlan& plan = plans[k];
    const bool resumed = restart && k == k0;
    if (!resumed) stepper.begin(plan);
    for (size_t i = resumed ? i0 : 0; i < plan.taus.size(); ++i) {
      stepper.advance(u, plan.taus[i]);
      char what[160];
      std::snprintf(what, sizeof what, "state %s %.3g", plan.name.c_str(), plan.taus[i]);
      progress.step(++done, what, stats.newton_iterations);
      const bool last = i + 1 == plan.taus.size();
      // A signal stops the run at this step boundary, the step written first.
      const int signal = interrupt_requested(comm);
      if (last || (i + 1) % config.output.every == 0 || signal)
        recorder.record(static_cast<double>(k) + plan.taus[i], u,
                        stepper.load_factor(plan.taus[i]));
      if (checkpoints.due(signal)) {
        nlohmann::json position = {{"state", k},
                                   {"increment", i + 1},
                                   {"state_time", static_cast<double>(k) + plan.taus[i]},
                                   {"stepper", stepper.position()},
                                   {"constraints", constraint_states(constraints)},
                                   {"states", run.states},
                                   {"last", last && k + 1 == plans.size()}};
        checkpoints.write(position,
                          {{"displacement", u}, {"previous_displacement", stepper.u_last()}});
      }
      if (signal) throw Interrupted(signal);
    }
    if (plan.first)
      for (int c = 0; c < constraints.size(); ++c)
        constraints[c].rest_measure = constraints[c].measure;
    nlohmann::json state;
    state["name"] = plan.name;
    state["time"] = static_cast<double>(k + 1);
    // Its output step in this run's .h5 (null: written by the run restarted from).
    state["step"] = recorder.written() > 0 ? nlohmann::json(recorder.written() - 1) : nullptr;
    state["load_factor"] = stepper.load_factor(plan.taus.back());
    if (config.tip) {
      const TipOrientation t = tip_orientation(problem, config.tip->group, config.gravity, u);
      state["tip"] = {{"group", config.tip->group},
                      {"inclination_deg", t.inclination_deg},
                      {"rotation_deg", t.rotation_deg}};
    }
    double added = 0, change = 0;
    for (int c = 0; c < constraints.size(); ++c) {
      if (!constraints[c].is_cavity()) continue;
      added += constraints[c].measure - constraints[c].rest_measure;
      change += constraints[c].measure - constraints[c].reference_measure;
    }
    state["added_volume_ml"] = added * 1e6;
    state["volume_change_ml"] = change * 1e6;
    const nlohmann::json actuators = constraints.report();
    state["cavities"] = actuators["cavities"];
    state["cables"] = actuators["cables"];
    run.states.push_back(state);
  }
  return run;
}

}  // namespace hs
