#include "solvers/stepping/state_plan.hpp"

#include <sstream>

#include "common/error.hpp"

namespace hs {

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
    for (const auto& [cavity, target] : states[k].cavities)
      p.ramps.push_back(
          {cavity, target.pressure ? Constraint::Control::multiplier : Constraint::Control::measure,
           0, target.pressure ? *target.pressure : *target.added_volume});
    p.moves = BoundaryMoves(states[k].moves);
    plans.push_back(p);
  }
  return plans;
}

const StatePlan::Ramp* StatePlan::ramp_of(const Constraint& c) const {
  for (const Ramp& r : ramps)
    if (r.constraint == c.name()) return &r;
  return nullptr;
}

void StatePlan::begin(ConstraintSet& constraints, const std::string& deck_path) {
  for (Ramp& ramp : ramps) {
    Constraint& cav = constraints[constraints.find(ramp.constraint)];
    if (ramp.control == Constraint::Control::multiplier) {
      ramp.from = cav.multiplier();
    } else {
      ramp.from = cav.measure();
      const double added = ramp.to;
      ramp.to += cav.rest_measure();  // added volume is counted from the end of the first state
      // Walls cannot pass through each other (no contact): a volume <= 0 has no solution.
      if (!(ramp.to > 0)) {
        std::ostringstream msg;
        msg << deck_path << ": state '" << name << "': cavity '" << cav.name() << "': added_volume "
            << added << " m^3 would leave it a volume of " << ramp.to << " m^3 (it holds "
            << cav.rest_measure()
            << " m^3 at the end of the first state); a cavity's volume must stay > 0";
        throw InputError(msg.str());
      }
    }
    cav.prescribe(ramp.control, ramp.from);
  }
}

void StatePlan::set_targets(ConstraintSet& constraints, double tau) const {
  for (int c = 0; c < constraints.size(); ++c) {
    Constraint& cav = constraints[c];
    if (const Ramp* ramp = ramp_of(cav))
      cav.set_target(ramp->from + tau * (ramp->to - ramp->from));
    else
      cav.set_target(first ? cav.first_state_target(tau) : cav.target());
  }
}

std::string StatePlan::failure_note(const ConstraintSet& constraints) const {
  // A pressure ramped past the cavity's pressure extremum (the peak of an inflation, the
  // buckling of walls under suction) has no equilibrium nearby.
  std::ostringstream msg;
  for (int c = 0; c < constraints.size(); ++c) {
    const Constraint& cav = constraints[c];
    if (!ramp_of(cav) && !(first && cav.ramped_in_first_state())) continue;
    const std::string note = cav.ramp_failure_note();
    if (!note.empty()) msg << "; " << note;
  }
  return msg.str();
}

nlohmann::json StatePlan::ramps_json(const ConstraintSet& constraints) const {
  nlohmann::json list = nlohmann::json::array();
  for (int c = 0; c < constraints.size(); ++c) {
    const Ramp* r = ramp_of(constraints[c]);
    list.push_back({{"active", r != nullptr},
                    {"control", static_cast<int>(r ? r->control : Constraint::Control::multiplier)},
                    {"from", r ? r->from : 0.0},
                    {"to", r ? r->to : 0.0}});
  }
  return list;
}

void StatePlan::resume_ramps(const nlohmann::json& list, const ConstraintSet& constraints) {
  for (Ramp& ramp : ramps) {
    const auto& r = list.at(constraints.find(ramp.constraint));
    ramp.control = static_cast<Constraint::Control>(r.at("control").get<int>());
    ramp.from = r.at("from");
    ramp.to = r.at("to");
  }
}

}  // namespace hs
