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

void StatePlan::begin(ConstraintSet& constraints, const std::string& deck_path) {
  for (int c = 0; c < constraints.size(); ++c) {
    auto& ramp = ramps[c];
    if (!ramp.active) continue;
    Constraint& cav = constraints[c];
    if (ramp.control == Constraint::Control::multiplier) {
      ramp.from = cav.lambda;
    } else {
      ramp.from = cav.measure;
      const double added = ramp.to;
      ramp.to += cav.rest_measure;  // added volume is counted from the end of the first state
      // Walls cannot pass through each other (no contact): a volume <= 0 has no solution.
      if (!(ramp.to > 0)) {
        std::ostringstream msg;
        msg << deck_path << ": state '" << name << "': cavity '" << cav.name() << "': added_volume "
            << added << " m^3 would leave it a volume of " << ramp.to << " m^3 (it holds "
            << cav.rest_measure
            << " m^3 at the end of the first state); a cavity's volume must stay > 0";
        throw InputError(msg.str());
      }
    }
    cav.control = ramp.control;
  }
}

void StatePlan::set_targets(ConstraintSet& constraints, double tau) const {
  for (int c = 0; c < constraints.size(); ++c) {
    Constraint& cav = constraints[c];
    const auto& ramp = ramps[c];
    if (ramp.active) {
      cav.target = ramp.from + tau * (ramp.to - ramp.from);
    } else if (first) {
      if (cav.control == Constraint::Control::multiplier)
        cav.target = tau * cav.first_state_multiplier;
      if (cav.control == Constraint::Control::measure)
        cav.target = cav.reference_measure + tau * cav.first_state_measure_change.value_or(0.0);
    }
    if (cav.control == Constraint::Control::multiplier) cav.lambda = cav.target;
  }
}

std::string StatePlan::failure_note(const ConstraintSet& constraints) const {
  // A pressure ramped past the cavity's pressure extremum (the peak of an inflation, the
  // buckling of walls under suction) has no equilibrium nearby.
  std::ostringstream msg;
  for (int c = 0; c < constraints.size(); ++c) {
    const Constraint& cav = constraints[c];
    const bool ramped = ramps[c].active || (first && cav.first_state_multiplier != 0);
    if (ramped && cav.is_cavity() && cav.control == Constraint::Control::multiplier &&
        cav.target != 0)
      msg << "; cavity '" << cav.name() << "' was at " << cav.target
          << " Pa on a pressure ramp (past a pressure peak or a buckling of the walls there "
             "is no equilibrium under pressure control: prescribe added_volume to pass it)";
  }
  return msg.str();
}

nlohmann::json StatePlan::ramps_json() const {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& r : ramps)
    list.push_back({{"active", r.active},
                    {"control", static_cast<int>(r.control)},
                    {"from", r.from},
                    {"to", r.to}});
  return list;
}

void StatePlan::resume_ramps(const nlohmann::json& list) {
  for (size_t c = 0; c < ramps.size(); ++c) {
    const auto& r = list.at(c);
    ramps[c].active = r.at("active");
    ramps[c].control = static_cast<Constraint::Control>(r.at("control").get<int>());
    ramps[c].from = r.at("from");
    ramps[c].to = r.at("to");
  }
}

}  // namespace hs
