// parse_control_section: the end effectors of a soft robot, the cavities that actuate it and
// the targets its effectors are driven to (docs/decks.md, "control"; docs/control.md).
#include "deck/control_section.hpp"

#include <algorithm>
#include <string>
#include <vector>

#include "deck/cavity_sections.hpp"

namespace hs {
namespace {

EffectorConfig parse_effector(const DeckReader& r, const YAML::Node& node, const std::string& key) {
  r.check_map(node, key, {"name", "point", "position", "directions", "weight"});
  EffectorConfig e;
  e.name = r.text(required(r, node, key, "name"), child_key(key, "name"));
  // A mesh node or a material point inside an element: one of them, not both.
  if (static_cast<bool>(node["point"]) == static_cast<bool>(node["position"]))
    r.fail(key, node,
           "give exactly one of point (a point group with one node) or position (a material "
           "point, in reference coordinates)");
  if (const auto n = node["point"]) e.point = r.text(n, child_key(key, "point"));
  if (const auto n = node["position"]) e.position = r.vector3(n, child_key(key, "position"));
  if (const auto n = node["directions"]) {
    const std::string dkey = child_key(key, "directions");
    r.check_list(n, dkey);
    require(n.size() > 0, r, n, dkey, "must name at least one of x, y, z");
    e.directions = {false, false, false};
    for (size_t i = 0; i < n.size(); ++i) {
      const std::string d = one_of(r, n[i], item_key(dkey, i), {"x", "y", "z"});
      bool& on = e.directions[d[0] - 'x'];
      require(!on, r, n[i], item_key(dkey, i), "direction '" + d + "' named twice");
      on = true;
    }
  }
  if (const auto n = node["weight"]) {
    e.weight = r.number(n, child_key(key, "weight"));
    require(e.weight > 0, r, n, child_key(key, "weight"),
            "must be > 0, got " + format_number(e.weight));
  }
  return e;
}

std::vector<EffectorConfig> parse_effectors(const DeckReader& r, const YAML::Node& node,
                                            const std::string& key) {
  r.check_list(node, key);
  require(node.size() > 0, r, node, key, "at least one effector is required");
  std::vector<EffectorConfig> effectors;
  for (size_t i = 0; i < node.size(); ++i) {
    const std::string ekey = item_key(key, i);
    effectors.push_back(parse_effector(r, node[i], ekey));
    for (size_t j = 0; j < i; ++j)
      if (effectors[j].name == effectors[i].name)
        r.fail(child_key(ekey, "name"), node[i]["name"],
               "duplicate effector name '" + effectors[i].name + "' (also in " + item_key(key, j) +
                   ")");
  }
  return effectors;
}

// Optional bounds `low_name` <= `high_name` (unset: unbounded); the lower one must not exceed
// the upper one.
void parse_bounds(const DeckReader& r, const YAML::Node& node, const std::string& key,
                  const std::string& low_name, const std::string& high_name, double& low,
                  double& high) {
  if (const auto n = node[low_name]) low = r.number(n, child_key(key, low_name));
  if (const auto n = node[high_name]) high = r.number(n, child_key(key, high_name));
  if (low > high)
    r.fail(child_key(key, low_name), node[low_name],
           "is " + format_number(low) + " but " + high_name + " is " + format_number(high) +
               " (the lower bound must not exceed the upper one)");
}

// A cable actuator: bounds on its tension (N) and its pull (its shortening, m).
ActuatorConfig parse_cable_actuator(const DeckReader& r, const YAML::Node& node,
                                    const std::string& key,
                                    const std::vector<CableConfig>& cables) {
  r.check_map(node, key,
              {"cable", "min_force", "max_force", "min_pull", "max_pull", "max_force_change"});
  ActuatorConfig a;
  a.min_multiplier = 0;  // a cable cannot push
  const YAML::Node cable = node["cable"];
  const std::string ckey = child_key(key, "cable");
  a.constraint = r.text(cable, ckey);
  std::vector<std::string> names;
  for (const auto& c : cables) names.push_back(c.name);
  if (!contains(names, a.constraint))
    r.fail(ckey, cable,
           names.empty() ? "not a declared cable (the deck has no cables section)"
                         : "not a declared cable (did you mean '" + nearest(a.constraint, names) +
                               "'? cables: " + join(names) + ")");
  parse_bounds(r, node, key, "min_force", "max_force", a.min_multiplier, a.max_multiplier);
  if (a.min_multiplier < 0)
    r.fail(child_key(key, "min_force"), node["min_force"],
           "must be >= 0 (a cable pulls, it cannot push), got " + format_number(a.min_multiplier));
  parse_bounds(r, node, key, "min_pull", "max_pull", a.min_measure_change, a.max_measure_change);
  if (const auto n = node["max_force_change"]) {
    a.max_multiplier_step = r.number(n, child_key(key, "max_force_change"));
    require(a.max_multiplier_step > 0, r, n, child_key(key, "max_force_change"),
            "must be > 0, got " + format_number(a.max_multiplier_step));
  }
  return a;
}

ActuatorConfig parse_actuator(const DeckReader& r, const YAML::Node& node, const std::string& key,
                              const std::vector<CavityConfig>& cavities,
                              const std::vector<CableConfig>& cables) {
  if (node.IsMap() && node["cable"]) {
    if (node["cavity"])
      r.fail(child_key(key, "cable"), node["cable"], "give one of cavity and cable, not both");
    return parse_cable_actuator(r, node, key, cables);
  }
  r.check_map(node, key,
              {"cavity", "min_pressure", "max_pressure", "min_volume_growth", "max_volume_growth",
               "max_pressure_change"});
  ActuatorConfig a;
  const YAML::Node cavity = required(r, node, key, "cavity");
  const std::string ckey = child_key(key, "cavity");
  a.constraint = r.text(cavity, ckey);
  std::vector<std::string> names;
  for (const auto& c : cavities) names.push_back(c.group);
  const auto found = std::find(names.begin(), names.end(), a.constraint);
  if (found == names.end())
    r.fail(ckey, cavity,
           names.empty() ? "not a declared cavity (the deck has no cavities section)"
                         : "not a declared cavity (did you mean '" + nearest(a.constraint, names) +
                               "'? cavities: " + join(names) + ")");
  const CavityKind kind = cavities[found - names.begin()].kind;
  if (!is_actuated(kind))
    r.fail(ckey, cavity,
           "cavity '" + a.constraint + "' is " + name_of(kCavityKindNames, kind) +
               ": sealed chambers are not actuated, so control cannot drive them (use a "
               "pneumatic or hydraulic cavity)");

  parse_bounds(r, node, key, "min_pressure", "max_pressure", a.min_multiplier, a.max_multiplier);
  parse_bounds(r, node, key, "min_volume_growth", "max_volume_growth", a.min_measure_change,
               a.max_measure_change);
  if (const auto n = node["max_pressure_change"]) {
    a.max_multiplier_step = r.number(n, child_key(key, "max_pressure_change"));
    require(a.max_multiplier_step > 0, r, n, child_key(key, "max_pressure_change"),
            "must be > 0, got " + format_number(a.max_multiplier_step));
  }
  return a;
}

std::vector<ActuatorConfig> parse_actuators(const DeckReader& r, const YAML::Node& node,
                                            const std::string& key,
                                            const std::vector<CavityConfig>& cavities,
                                            const std::vector<CableConfig>& cables) {
  r.check_list(node, key);
  require(node.size() > 0, r, node, key, "at least one actuator is required");
  std::vector<ActuatorConfig> actuators;
  for (size_t i = 0; i < node.size(); ++i) {
    const std::string akey = item_key(key, i);
    actuators.push_back(parse_actuator(r, node[i], akey, cavities, cables));
    const char* what = node[i]["cable"] ? "cable" : "cavity";
    for (size_t j = 0; j < i; ++j)
      if (actuators[j].constraint == actuators[i].constraint)
        r.fail(child_key(akey, what), node[i][what],
               std::string("duplicate actuator ") + what + " '" + actuators[i].constraint +
                   "' (also in " + item_key(key, j) + ")");
  }
  return actuators;
}

// The target sets, in order: each a map effector name -> [x, y, z], kept in the deck's order.
std::vector<std::vector<ControlTarget>> parse_control_targets(
    const DeckReader& r, const YAML::Node& node, const std::string& key,
    const std::vector<EffectorConfig>& effectors) {
  r.check_list(node, key);
  require(node.size() > 0, r, node, key,
          "must hold at least one target set (leave targets out when the command line gives "
          "them)");
  std::vector<std::string> names;
  for (const auto& e : effectors) names.push_back(e.name);
  std::vector<std::vector<ControlTarget>> sets;
  for (size_t i = 0; i < node.size(); ++i) {
    const std::string skey = item_key(key, i);
    if (!node[i].IsMap()) r.fail(skey, node[i], "expected a map of effector name: [x, y, z]");
    require(node[i].size() > 0, r, node[i], skey,
            "an empty target set (name at least one effector: " + join(names) + ")");
    std::vector<ControlTarget> set;
    for (const auto& entry : node[i]) {
      const std::string name = entry.first.Scalar(), tkey = child_key(skey, name);
      for (const auto& t : set)
        if (t.effector == name) r.fail(tkey, entry.first, "duplicate key");
      if (!contains(names, name))
        r.fail(tkey, entry.first,
               "not an effector (did you mean '" + nearest(name, names) +
                   "'? effectors: " + join(names) + ")");
      set.push_back(ControlTarget{name, r.vector3(entry.second, tkey)});
    }
    sets.push_back(set);
  }
  return sets;
}

ControlConfig parse_control(const DeckReader& r, const YAML::Node& node,
                            const std::vector<CavityConfig>& cavities,
                            const std::vector<CableConfig>& cables) {
  const std::string key = "control";
  if (node.IsMap() && node["targets_from_stdin"])
    r.fail(child_key(key, "targets_from_stdin"), node["targets_from_stdin"],
           "not a deck key: the command line sets it (--targets -)");
  r.check_map(
      node, key,
      {"effectors", "actuators", "targets", "steps_per_target", "regularization", "newton_finish",
       "free_solve", "refactor_every", "check_equilibrium", "factor_threads"});
  ControlConfig control;
  control.effectors =
      parse_effectors(r, required(r, node, key, "effectors"), child_key(key, "effectors"));
  control.actuators = parse_actuators(r, required(r, node, key, "actuators"),
                                      child_key(key, "actuators"), cavities, cables);
  if (const auto n = node["targets"])
    control.targets = parse_control_targets(r, n, child_key(key, "targets"), control.effectors);
  if (const auto n = node["steps_per_target"]) {
    control.steps_per_target = r.integer(n, "control.steps_per_target");
    require(control.steps_per_target >= 1, r, n, "control.steps_per_target",
            "must be >= 1, got " + std::to_string(control.steps_per_target));
  }
  if (const auto n = node["regularization"]) {
    control.regularization = r.number(n, "control.regularization");
    require(control.regularization >= 0, r, n, "control.regularization",
            "must be >= 0, got " + format_number(control.regularization));
  }
  if (const auto n = node["newton_finish"])
    control.newton_finish = r.boolean(n, "control.newton_finish");
  if (const auto n = node["free_solve"])
    control.free_solve = enum_of<FreeSolve>(
        kFreeSolveNames, one_of(r, n, child_key(key, "free_solve"), kFreeSolveNames));
  if (const auto n = node["refactor_every"]) {
    control.refactor_every = r.integer(n, "control.refactor_every");
    require(control.refactor_every >= 1, r, n, "control.refactor_every",
            "must be >= 1, got " + std::to_string(control.refactor_every));
    require(control.refactor_every == 1 || control.free_solve == FreeSolve::one_step, r, n,
            "control.refactor_every", "needs free_solve: one_step (Newton refactors every step)");
  }
  if (const auto n = node["check_equilibrium"])
    control.check_equilibrium = r.boolean(n, "control.check_equilibrium");
  if (const auto n = node["factor_threads"]) {
    control.factor_threads = r.integer(n, "control.factor_threads");
    require(control.factor_threads >= 0 && control.factor_threads <= 64, r, n,
            "control.factor_threads",
            "must be 0 ... 64, got " + std::to_string(control.factor_threads));
    require(control.factor_threads == 0 || control.free_solve == FreeSolve::one_step, r, n,
            "control.factor_threads", "needs free_solve: one_step");
  }
  return control;
}

}  // namespace

void parse_control_section(const DeckReader& r, const YAML::Node& root, Config& c) {
  // Control steps from one static equilibrium to the next; dynamic runs have no cavities.
  if (c.time.type == TimeType::dynamic)
    forbid(r, root, "", "control",
           "control needs time.type static or quasi_static (time.type is dynamic)");
  if (const auto n = root["control"]) c.control = parse_control(r, n, c.cavities, c.cables);
}

}  // namespace hs
