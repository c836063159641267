// parse_cavity_sections: the cavities of a soft robot, the states a run goes through and the
// tip it reports (docs/decks.md, "Cavities, states and tip").
#include "deck/cavity_sections.hpp"

#include <algorithm>
#include <map>
#include <string>
#include <vector>

namespace hs {
namespace {

FluidWeightConfig parse_fluid_weight(const DeckReader& r, const YAML::Node& node,
                                     const std::string& key) {
  r.check_map(node, key, {"method", "grid", "device", "coupling"});
  FluidWeightConfig w;
  if (const auto n = node["method"])
    w.method = enum_of<WeightMethod>(kWeightMethodNames,
                                     one_of(r, n, child_key(key, "method"), kWeightMethodNames));
  const std::string method = name_of(kWeightMethodNames, w.method);
  if (w.method == WeightMethod::column) {
    if (const auto n = node["grid"]) {
      w.grid = r.integer(n, child_key(key, "grid"));
      require(w.grid >= 1, r, n, child_key(key, "grid"),
              "must be >= 1, got " + std::to_string(w.grid));
      // N^2 columns, each with its own hits: 8192^2 is 6.7e7 columns, past any cavity's need
      // (200-1000 resolve the meshes of docs/fluidweight.md) and within memory.
      require(w.grid <= 8192, r, n, child_key(key, "grid"),
              "must be <= 8192, got " + std::to_string(w.grid));
    }
  } else {
    forbid(r, node, key, "grid", "only used by method column (method is " + method + ")");
  }
  if (const auto n = node["device"]) {
    w.device = enum_of<WeightDevice>(kWeightDeviceNames,
                                     one_of(r, n, child_key(key, "device"), kWeightDeviceNames));
    // Only the column method has CUDA kernels (cuda/, docs/fluidweight.md).
    require(w.device == WeightDevice::cpu || w.method == WeightMethod::column, r, n,
            child_key(key, "device"),
            "cuda is only used by method column (method is " + method + ", which runs on the cpu)");
  }
  if (const auto n = node["coupling"])
    w.coupling = enum_of<WeightCoupling>(
        kWeightCouplingNames, one_of(r, n, child_key(key, "coupling"), kWeightCouplingNames));
  return w;
}

CavityConfig parse_cavity(const DeckReader& r, const YAML::Node& node, const std::string& key) {
  r.check_map(node, key,
              {"group", "kind", "pressure", "added_volume", "density", "fluid_weight",
               "initial_pressure", "atmospheric_pressure"});
  CavityConfig cavity;
  cavity.group = r.text(required(r, node, key, "group"), child_key(key, "group"));
  if (const auto n = node["kind"])
    cavity.kind = enum_of<CavityKind>(kCavityKindNames,
                                      one_of(r, n, child_key(key, "kind"), kCavityKindNames));
  const std::string this_kind = " (this cavity is " + name_of(kCavityKindNames, cavity.kind) + ")";

  if (is_actuated(cavity.kind)) {
    // With added_volume the pressure is an unknown of the run, so it cannot be given too.
    if (node["pressure"] && node["added_volume"])
      r.fail(key, node,
             "give either pressure or added_volume, not both (with added_volume the pressure is "
             "an unknown)");
    if (const auto n = node["pressure"]) cavity.pressure = r.number(n, child_key(key, "pressure"));
    if (const auto n = node["added_volume"])
      cavity.added_volume = r.number(n, child_key(key, "added_volume"));
  } else {
    const std::string reason =
        "only used by kinds pneumatic and hydraulic (a sealed chamber is not actuated)" + this_kind;
    forbid(r, node, key, "pressure", reason);
    forbid(r, node, key, "added_volume", reason);
  }

  if (cavity.kind == CavityKind::hydraulic) {
    if (const auto n = node["density"]) {
      cavity.density = r.number(n, child_key(key, "density"));
      require(cavity.density >= 0, r, n, child_key(key, "density"),
              "must be >= 0, got " + format_number(cavity.density));
    }
    if (const auto n = node["fluid_weight"])
      cavity.fluid_weight = parse_fluid_weight(r, n, child_key(key, "fluid_weight"));
  } else {
    forbid(r, node, key, "density",
           "only used by kind hydraulic (the liquid's density)" + this_kind);
    forbid(r, node, key, "fluid_weight",
           "only used by kind hydraulic (how the liquid's weight reaches the walls)" + this_kind);
  }

  if (cavity.kind == CavityKind::sealed_gas) {
    if (const auto n = node["initial_pressure"])
      cavity.initial_pressure = r.number(n, child_key(key, "initial_pressure"));
    if (const auto n = node["atmospheric_pressure"]) {
      cavity.atmospheric_pressure = r.number(n, child_key(key, "atmospheric_pressure"));
      require(cavity.atmospheric_pressure > 0, r, n, child_key(key, "atmospheric_pressure"),
              "must be > 0, got " + format_number(cavity.atmospheric_pressure));
    }
    // (p + p_atm) V = const needs a positive absolute pressure.
    const double absolute = cavity.initial_pressure + cavity.atmospheric_pressure;
    require(absolute > 0, r, node["initial_pressure"], child_key(key, "initial_pressure"),
            "gives the absolute pressure initial_pressure + atmospheric_pressure = " +
                format_number(absolute) + ", must be > 0");
  } else {
    const std::string reason = "only used by kind sealed_gas" + this_kind;
    forbid(r, node, key, "initial_pressure", reason);
    forbid(r, node, key, "atmospheric_pressure", reason);
  }
  return cavity;
}

std::vector<CavityConfig> parse_cavities(const DeckReader& r, const YAML::Node& node) {
  r.check_list(node, "cavities");
  std::vector<CavityConfig> cavities;
  for (size_t i = 0; i < node.size(); ++i) {
    const std::string key = item_key("cavities", i);
    cavities.push_back(parse_cavity(r, node[i], key));
    for (size_t j = 0; j < i; ++j)
      if (cavities[j].group == cavities[i].group)
        r.fail(child_key(key, "group"), node[i]["group"],
               "duplicate cavity group '" + cavities[i].group + "' (also in " +
                   item_key("cavities", j) + ")");
  }
  return cavities;
}

// The targets of a later state: cavity name -> {pressure: P} or {added_volume: V}.
std::map<std::string, CavityTarget> parse_targets(const DeckReader& r, const YAML::Node& node,
                                                  const std::string& key,
                                                  const std::vector<CavityConfig>& cavities) {
  if (!node.IsMap())
    r.fail(key, node, "expected a map of cavity name: {pressure: P} or {added_volume: V}");
  std::vector<std::string> names;
  for (const auto& cavity : cavities) names.push_back(cavity.group);
  std::map<std::string, CavityTarget> targets;
  for (const auto& entry : node) {
    const std::string name = entry.first.Scalar(), ckey = child_key(key, name);
    if (targets.count(name)) r.fail(ckey, entry.first, "duplicate key");
    const auto found = std::find(names.begin(), names.end(), name);
    if (found == names.end())
      r.fail(ckey, entry.first,
             names.empty() ? "not a declared cavity (the deck has no cavities section)"
                           : "not a declared cavity (did you mean '" + nearest(name, names) +
                                 "'? cavities: " + join(names) + ")");
    const CavityKind kind = cavities[found - names.begin()].kind;
    if (!is_actuated(kind))
      r.fail(ckey, entry.first,
             "cavity '" + name + "' is " + name_of(kCavityKindNames, kind) +
                 ": sealed chambers are not actuated, so a state cannot set them");
    const YAML::Node target = entry.second;
    r.check_map(target, ckey, {"pressure", "added_volume"});
    if (static_cast<bool>(target["pressure"]) == static_cast<bool>(target["added_volume"]))
      r.fail(ckey, target, "give exactly one of pressure or added_volume");
    CavityTarget t;
    if (const auto n = target["pressure"]) t.pressure = r.number(n, child_key(ckey, "pressure"));
    if (const auto n = target["added_volume"])
      t.added_volume = r.number(n, child_key(ckey, "added_volume"));
    targets[name] = t;
  }
  return targets;
}

std::vector<StateConfig> parse_states(const DeckReader& r, const YAML::Node& node,
                                      const std::vector<CavityConfig>& cavities) {
  r.check_list(node, "states");
  require(node.size() > 0, r, node, "states",
          "must hold at least one state (leave states out for one load ramp over time.steps)");
  std::vector<StateConfig> states;
  for (size_t i = 0; i < node.size(); ++i) {
    const std::string key = item_key("states", i);
    r.check_map(node[i], key, {"name", "steps", "cavities"});
    StateConfig s;
    s.name = r.text(required(r, node[i], key, "name"), child_key(key, "name"));
    for (size_t j = 0; j < i; ++j)
      if (states[j].name == s.name)
        r.fail(child_key(key, "name"), node[i]["name"],
               "duplicate state name '" + s.name + "' (also in " + item_key("states", j) + ")");
    if (const auto n = node[i]["steps"]) {
      s.steps = r.integer(n, child_key(key, "steps"));
      require(s.steps >= 1, r, n, child_key(key, "steps"),
              "must be >= 1, got " + std::to_string(s.steps));
    }
    if (const auto n = node[i]["cavities"]) {
      // The first state is where the load (and the cavities' own controls) goes from 0 to
      // full; a target there would say two things about the same ramp.
      require(i > 0, r, n, child_key(key, "cavities"),
              "not allowed in the first state: it ramps the load and the cavities' own controls "
              "(cavities[].pressure or added_volume) from 0 to full; give targets in later "
              "states");
      s.cavities = parse_targets(r, n, child_key(key, "cavities"), cavities);
    }
    states.push_back(s);
  }
  return states;
}

TipConfig parse_tip(const DeckReader& r, const YAML::Node& node) {
  r.check_map(node, "tip", {"group"});
  TipConfig tip;
  tip.group = r.text(required(r, node, "tip", "group"), "tip.group");
  return tip;
}

}  // namespace

void parse_cavity_sections(const DeckReader& r, const YAML::Node& root, Config& c) {
  // Dynamic runs have no states to step through and no cavity equations in their time
  // integrator.
  if (c.time.type == TimeType::dynamic)
    for (const char* name : {"cavities", "states", "tip"})
      forbid(r, root, "", name,
             std::string(name == std::string("tip") ? "the tip is reported per state: " : "") +
                 "cavities and states need time.type static or quasi_static (time.type is "
                 "dynamic)");

  if (const auto n = root["cavities"]) c.cavities = parse_cavities(r, n);
  if (const auto n = root["states"]) {
    // The first state's steps replace time.steps; its ramp is linear, so no schedule either.
    // parse_time has checked that time is a map.
    if (const auto time = root["time"]) {
      forbid(r, time, "time", "steps",
             "not used when states are given (the first state's steps replace it)");
      forbid(r, time, "time", "schedule",
             "not used when states are given (the first state ramps the load linearly over its "
             "steps)");
    }
    c.states = parse_states(r, n, c.cavities);
    c.time.steps = c.states.front().steps;
  }
  if (const auto n = root["tip"]) c.tip = parse_tip(r, n);
}

}  // namespace hs
