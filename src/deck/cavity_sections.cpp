// The sections `cavities` and `states` and the map of `tip`: the cavities of a soft robot, the
// states a run goes through and the face it reports (docs/decks.md, "Cavities, states and tip").
#include "deck/cavity_sections.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "deck/section_keys.hpp"

namespace hs {
namespace {

std::string this_kind(const CavityConfig& cavity) {
  return " (this cavity is " + name_of(kCavityKindNames, cavity.kind) + ")";
}

// A cavity key of some kinds only; the reason names the cavity's kind.
KeyUse<CavityConfig> kinds_only(bool (*holds)(CavityKind), const std::string& reason,
                                const std::string& doc) {
  return {[holds](const CavityConfig& cavity, const Config&) { return holds(cavity.kind); },
          [reason](const CavityConfig& cavity) { return reason + this_kind(cavity); }, doc};
}

bool is_hydraulic(CavityKind kind) { return kind == CavityKind::hydraulic; }
bool is_sealed_gas(CavityKind kind) { return kind == CavityKind::sealed_gas; }
bool is_pressure_limited(CavityKind kind) { return kind == CavityKind::pressure_limited; }
bool takes_added_volume(CavityKind kind) { return is_actuated(kind) || is_pressure_limited(kind); }

FluidWeightConfig parse_fluid_weight(const DeckReader& r, const YAML::Node& node,
                                     const std::string& key, const Config& c) {
  FluidWeightConfig w;
  read_keys(r, node, key, fluid_weight_keys(), w, c);
  // The column methods run on the GPU (cuda/, docs/fluidweight.md); the closed form, a loop
  // over the wall's triangles, runs on the cpu within the assembly.
  if (w.device == WeightDevice::cuda && w.method == WeightMethod::hydrostatic)
    r.fail(child_key(key, "device"), node["device"],
           "cuda is only used by the column methods (method is hydrostatic, which runs on the "
           "cpu)");
  return w;
}

CavityConfig parse_cavity(const DeckReader& r, const YAML::Node& node, const std::string& key,
                          const Config& c) {
  CavityConfig cavity;
  read_keys(r, node, key, cavity_keys(), cavity, c);
  // With added_volume the pressure is an unknown of the run, so it cannot be given too.
  if (node["pressure"] && node["added_volume"])
    r.fail(key, node,
           "give either pressure or added_volume, not both (with added_volume the pressure is "
           "an unknown)");
  if (cavity.kind == CavityKind::sealed_gas) {
    // (p + p_atm) V = const needs a positive absolute pressure.
    const double absolute = cavity.initial_pressure + cavity.atmospheric_pressure;
    require(absolute > 0, r, node["initial_pressure"], child_key(key, "initial_pressure"),
            "gives the absolute pressure initial_pressure + atmospheric_pressure = " +
                format_number(absolute) + ", must be > 0");
  }
  if (cavity.kind == CavityKind::pressure_limited) {
    require(cavity.added_volume.has_value(), r, node, key,
            "a pressure_limited cavity needs added_volume (the volume its pump delivers)");
    require(node["max_pressure"].IsDefined(), r, node, key,
            "a pressure_limited cavity needs max_pressure (where its relief valve opens)");
  }
  return cavity;
}

// The targets of a later state: cavity name -> {pressure: P} or {added_volume: V}.
std::map<std::string, CavityTarget> parse_targets(const DeckReader& r, const YAML::Node& node,
                                                  const std::string& key, const Config& c) {
  const std::vector<CavityConfig>& cavities = c.cavities;
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
                 ": only pneumatic and hydraulic cavities are actuated, so a state cannot set it");
    const YAML::Node target = entry.second;
    CavityTarget t;
    read_keys(r, target, ckey, target_keys(), t, c);
    if (!t.pressure == !t.added_volume)
      r.fail(ckey, target, "give exactly one of pressure or added_volume");
    targets[name] = t;
  }
  return targets;
}

// A dynamic run's states: each one's time (the first's 0 unless given) on a time step, in
// order, within the run, and a ramp of at least one time step after a step state.
void check_state_times(const DeckReader& r, const YAML::Node& node,
                       std::vector<StateConfig>& states, const TimeConfig& time) {
  const int64_t last_step = static_cast<int64_t>(std::ceil(time.end_time / time.dt - 1e-9));
  // A multiple of dt as people write it: 0.3, not 0.30000000000000004.
  auto seconds = [](double t) {
    char text[32];
    std::snprintf(text, sizeof text, "%.12g", t);
    return std::string(text);
  };
  for (size_t k = 0; k < states.size(); ++k) {
    const std::string key = child_key(item_key("states", k), "time");
    const YAML::Node at = node[k]["time"] ? node[k]["time"] : node[k];
    if (!states[k].time) {
      if (k > 0)
        r.fail(key, at,
               "required in a dynamic run after the first state: the time (s) at which the "
               "state's values are reached");
      states[k].time = 0.0;
    }
    const double t = *states[k].time;
    require(t >= 0, r, at, key, "must be >= 0, got " + format_number(t));
    const double steps = t / time.dt;
    if (std::abs(steps - std::round(steps)) > 1e-6 * std::max(1.0, steps))
      r.fail(key, at,
             format_number(t) +
                 " s is not on a time step (a multiple of time.dt = " + format_number(time.dt) +
                 " s; the nearest are " + seconds(std::floor(steps) * time.dt) + " and " +
                 seconds(std::ceil(steps) * time.dt) + ")");
    if (t > time.end_time * (1 + 1e-12))
      r.fail(key, at,
             format_number(t) + " s is after time.end_time, " + format_number(time.end_time) +
                 " s: the run never reaches it");
    if (k > 0 && t < *states[k - 1].time)
      r.fail(key, at,
             format_number(t) + " s is before the previous state's time, " +
                 format_number(*states[k - 1].time) + " s (" + item_key("states", k - 1) +
                 "): states run in order");
  }
  const std::vector<int64_t> steps = state_time_steps(states, time.dt);
  for (size_t k = 1; k < states.size(); ++k) {
    const std::string key = child_key(item_key("states", k), "time");
    const YAML::Node at = node[k]["time"];
    if (steps[k] > last_step)
      r.fail(key, at,
             "equals the previous state's time, so the step is applied over the time step "
             "after " +
                 format_number(*states[k].time) + " s, past time.end_time (" +
                 format_number(time.end_time) + " s): give a later time.end_time");
    if (steps[k] <= steps[k - 1])
      r.fail(key, at,
             format_number(*states[k].time) + " s leaves its ramp no time step: " +
                 item_key("states", k - 1) + " is a step applied over the time step up to " +
                 seconds(static_cast<double>(steps[k - 1]) * time.dt) + " s; give a later time");
  }
}

}  // namespace

std::map<std::string, std::array<double, 3>> parse_moves(const DeckReader& r,
                                                         const YAML::Node& node,
                                                         const std::string& key, const Config& c) {
  if (!node.IsMap()) r.fail(key, node, "expected a map of boundary group: [dx, dy, dz]");
  std::vector<std::string> names;
  for (const auto& bc : c.dirichlet)
    if (std::find(names.begin(), names.end(), bc.group) == names.end()) names.push_back(bc.group);
  std::map<std::string, std::array<double, 3>> moves;
  for (const auto& entry : node) {
    const std::string name = entry.first.Scalar(), gkey = child_key(key, name);
    if (moves.count(name)) r.fail(gkey, entry.first, "duplicate key");
    if (std::find(names.begin(), names.end(), name) == names.end())
      r.fail(gkey, entry.first,
             names.empty() ? "not a boundary group (the deck has no boundary section)"
                           : "not a boundary group (did you mean '" + nearest(name, names) +
                                 "'? boundary groups: " + join(names) + ")");
    for (const auto& bc : c.dirichlet)
      if (bc.group == name && bc.exact)
        r.fail(
            gkey, entry.first,
            "group '" + name + "' takes the exact solution's values, which a move cannot add to");
    moves[name] = r.vector3(entry.second, gkey);
  }
  return moves;
}

const KeyTable<FluidWeightConfig>& fluid_weight_keys() {
  static const KeyTable<FluidWeightConfig> keys = {
      enum_key("method", &FluidWeightConfig::method, kWeightMethodNames,
               "`hydrostatic`: the pressure ρ g d of the depth d below the cavity's highest point "
               "on every wall, in closed form (exact for a full cavity); `column`: the paper's "
               "column method (docs/fluidweight.md), each vertical column's weight on its floor "
               "(leaves out the head above each section: wrong where chambers stack, "
               "docs/cavities.md); `column_head`: the same columns with ρ g d on every floor and "
               "ceiling (leaves out the side walls). With either column method a "
               "static run without `control` estimates, at the end of each state, what the closed "
               "form would "
               "change (summary.json's `load_model_error`) and warns past 2 %"),
      // N^2 columns, each with its own hits: 8192^2 is 6.7e7 columns, past any cavity's need
      // (200-1000 resolve the meshes of docs/fluidweight.md) and within memory.
      integer_key("grid", &FluidWeightConfig::grid, within(1, 8192),
                  "the weight is sampled on a `grid` × `grid` set of columns")
          .only({[](const FluidWeightConfig& w, const Config&) {
                   return w.method != WeightMethod::hydrostatic;
                 },
                 [](const FluidWeightConfig& w) {
                   return "only used by the column methods (method is " +
                          name_of(kWeightMethodNames, w.method) + ")";
                 },
                 "`column`, `column_head`"}),
      // 4: the cylinder's coarse P2 cavity 0.4 % short of its volume (2: 1.7 %), at 4 times the
      // triangles (docs/cavities.md, "Curved walls").
      integer_key("subdivision", &FluidWeightConfig::subdivision, within(2, 64),
                  "each curved (Tri6) wall face reaches the weight's method as `subdivision` × "
                  "`subdivision` flat triangles through points of the face; the liquid they hold "
                  "falls short of the cavity's volume as 1 / subdivision² (docs/cavities.md, "
                  "\"Curved walls\")")
          .only({[](const FluidWeightConfig&, const Config& c) { return c.mesh.order == 2; },
                 [](const FluidWeightConfig&) {
                   return std::string(
                       "only used on P2 meshes (mesh.order is 1: a flat wall face "
                       "is its own triangle)");
                 },
                 "P2 meshes"}),
      enum_key("device", &FluidWeightConfig::device, kWeightDeviceNames,
               "`cpu` or `cuda` (`cuda` with the column methods only)"),
      enum_key("coupling", &FluidWeightConfig::coupling, kWeightCouplingNames,
               "`converged`: the weight is recomputed on every Newton iterate; `linearized`: its "
               "distribution is frozen at the start of each step and scaled with the volume"),
  };
  return keys;
}

const KeyTable<CavityConfig>& cavity_keys() {
  const std::string actuated =
      "only used by kinds pneumatic and hydraulic (the other kinds are not actuated)";
  static const KeyTable<CavityConfig> keys = {
      text_key("group", &CavityConfig::group, "name",
               "surface physical group of the cavity's walls (unique across cavities); also the "
               "cavity's name in `states`")
          .needed(),
      enum_key("kind", &CavityConfig::kind, kCavityKindNames,
               "`pneumatic` (gas at a controlled pressure or volume), `hydraulic` (liquid at a "
               "controlled pressure or volume), `sealed_gas` (a closed amount of gas), "
               "`sealed_volume` (a chamber whose volume stays fixed, e.g. sealed incompressible "
               "liquid; no weight), `pressure_limited` (a pump delivers `added_volume` through "
               "a relief valve that opens at `max_pressure`)"),
      number_key("pressure", &CavityConfig::pressure, any_number(),
                 "gauge pressure (Pa) at the end of the first state, ramped with the load factor")
          .only(kinds_only(is_actuated, actuated, "`pneumatic`, `hydraulic`"))
          .printed_when([](const CavityConfig& cavity) { return !cavity.added_volume; }),
      optional_number_key(
          "added_volume", &CavityConfig::added_volume,
          "volume (m³) added to the undeformed cavity by the end of the first state, ramped "
          "with the load factor (negative: withdrawn); the pressure is then an unknown. "
          "Excludes `pressure`. A value that would leave the cavity a volume ≤ 0 is refused "
          "before any work (its walls would have to pass through each other).")
          .only(kinds_only(takes_added_volume,
                           "only used by kinds pneumatic, hydraulic and pressure_limited",
                           "`pneumatic`, `hydraulic`, `pressure_limited`")),
      number_key("density", &CavityConfig::density, at_least(0),
                 "the liquid's density (kg/m³; water 1000, mercury 13600); 0 is a weightless "
                 "liquid")
          .only(kinds_only(is_hydraulic, "only used by kind hydraulic (the liquid's density)",
                           "`hydraulic`")),
      custom_key<CavityConfig>(
          "fluid_weight", "map", "see below",
          "how the liquid's weight (density × gravity) reaches the walls",
          [](const DeckReader& r, const YAML::Node& n, const std::string& key, CavityConfig& cavity,
             const Config& c) { cavity.fluid_weight = parse_fluid_weight(r, n, key, c); },
          [](YAML::Emitter& out, const CavityConfig& cavity, const Config& c) {
            out << YAML::Flow << YAML::BeginMap;
            write_keys(out, fluid_weight_keys(), cavity.fluid_weight, c);
            out << YAML::EndMap;
          })
          .only(kinds_only(is_hydraulic,
                           "only used by kind hydraulic (how the liquid's weight reaches the "
                           "walls)",
                           "`hydraulic`")),
      number_key("initial_pressure", &CavityConfig::initial_pressure, any_number(),
                 "gauge pressure (Pa) of the gas in the undeformed cavity")
          .only(kinds_only(is_sealed_gas, "only used by kind sealed_gas", "`sealed_gas`")),
      number_key("atmospheric_pressure", &CavityConfig::atmospheric_pressure, above(0),
                 "Pa; gauge + atmospheric is the absolute pressure, which must be > 0")
          .only(kinds_only(is_sealed_gas, "only used by kind sealed_gas", "`sealed_gas`")),
      number_key("max_pressure", &CavityConfig::max_pressure, above(0),
                 "gauge pressure (Pa) at which the relief valve opens: the pressure never "
                 "exceeds it, and the volume stays below what the pump delivered while it holds")
          .only(kinds_only(is_pressure_limited, "only used by kind pressure_limited",
                           "`pressure_limited`")),
  };
  return keys;
}

const KeyTable<CavityTarget>& target_keys() {
  static const KeyTable<CavityTarget> keys = {
      optional_number_key("pressure", &CavityTarget::pressure, "Pa"),
      optional_number_key("added_volume", &CavityTarget::added_volume,
                          "m³, relative to the volume at the end of the first state"),
  };
  return keys;
}

const KeyTable<StateConfig>& state_keys() {
  static const KeyTable<StateConfig> keys = {
      text_key("name", &StateConfig::name, "name", "unique; names the state in the output")
          .needed(),
      integer_key("steps", &StateConfig::steps, at_least(1), "increments of the state's ramp")
          .only(use_when<StateConfig>(
              [](const StateConfig&, const Config& c) { return c.time.type != TimeType::dynamic; },
              "not used when time.type is dynamic (the states' times and time.dt set the steps)",
              "static/quasi-static")),
      optional_number_key(
          "time", &StateConfig::time,
          "s: the time at which the state's values are reached, ramped linearly from the "
          "previous state's time (from t = 0 for the first state) and held after the last "
          "state until `time.end_time`. A time equal to the previous state's is a step, "
          "applied over the time step after it; the first state at time 0 applies its values "
          "from t = 0. On a time step (a multiple of `time.dt`), not before the previous "
          "state's, at most `time.end_time`")
          .only(use_when<StateConfig>(
              [](const StateConfig&, const Config& c) { return c.time.type == TimeType::dynamic; },
              "only used when time.type is dynamic", "dynamic"))
          .defaults_to("0 in the first state; required in later ones"),
      custom_key<StateConfig>(
          "cavities", "map cavity: target", "none",
          "not in the first state. Each target is `{pressure: P}` (Pa) or `{added_volume: V}` "
          "(m³), exactly one; pneumatic and hydraulic cavities only (sealed ones are not "
          "actuated)",
          [](const DeckReader& r, const YAML::Node& n, const std::string& key, StateConfig& s,
             const Config& c) { s.cavities = parse_targets(r, n, key, c); },
          [](YAML::Emitter& out, const StateConfig& s, const Config& c) {
            out << YAML::BeginMap;
            for (const auto& [name, target] : s.cavities) {
              out << YAML::Key << name << YAML::Value << YAML::Flow << YAML::BeginMap;
              write_keys(out, target_keys(), target, c);
              out << YAML::EndMap;
            }
            out << YAML::EndMap;
          })
          .printed_when([](const StateConfig& s) { return !s.cavities.empty(); }),
      custom_key<StateConfig>(
          "move", "map group: 3 numbers", "none",
          "not in the first state. A translation (m) added to a boundary group's prescribed "
          "displacement over the state, ramped with its steps, on the components the group "
          "prescribes (a palm that rises once the fingers hold what they grasp); later states "
          "keep it. Not for groups with `exact` values",
          [](const DeckReader& r, const YAML::Node& n, const std::string& key, StateConfig& s,
             const Config& c) { s.moves = parse_moves(r, n, key, c); },
          [](YAML::Emitter& out, const StateConfig& s, const Config&) {
            out << YAML::BeginMap;
            for (const auto& [group, by] : s.moves) {
              out << YAML::Key << group << YAML::Value;
              write_numbers(out, by.data(), 3);
            }
            out << YAML::EndMap;
          })
          .only(use_when<StateConfig>(
              [](const StateConfig&, const Config& c) { return c.time.type != TimeType::dynamic; },
              "not used when time.type is dynamic", "static/quasi-static"))
          .printed_when([](const StateConfig& s) { return !s.moves.empty(); }),
  };
  return keys;
}

const KeyTable<TipConfig>& tip_keys() {
  static const KeyTable<TipConfig> keys = {
      text_key("group", &TipConfig::group, "name",
               "surface group whose mean deformed normal is reported for every state")
          .needed(),
  };
  return keys;
}

std::vector<CavityConfig> parse_cavities(const DeckReader& r, const YAML::Node& node,
                                         const Config& c) {
  r.check_list(node, "cavities");
  std::vector<CavityConfig> cavities;
  for (size_t i = 0; i < node.size(); ++i) {
    const std::string key = item_key("cavities", i);
    cavities.push_back(parse_cavity(r, node[i], key, c));
    for (size_t j = 0; j < i; ++j)
      if (cavities[j].group == cavities[i].group)
        r.fail(child_key(key, "group"), node[i]["group"],
               "duplicate cavity group '" + cavities[i].group + "' (also in " +
                   item_key("cavities", j) + ")");
  }
  return cavities;
}

std::vector<StateConfig> parse_states(const DeckReader& r, const YAML::Node& node,
                                      const Config& c) {
  r.check_list(node, "states");
  require(node.size() > 0, r, node, "states",
          "must hold at least one state (leave states out for one load ramp over time.steps)");
  std::vector<StateConfig> states;
  for (size_t i = 0; i < node.size(); ++i) {
    const std::string key = item_key("states", i);
    // The first state is where the load (and the cavities' own controls) goes from 0 to
    // full; a target there would say two things about the same ramp.
    if (i == 0 && node[i].IsMap() && node[i]["cavities"])
      r.fail(child_key(key, "cavities"), node[i]["cavities"],
             "not allowed in the first state: it ramps the load and the cavities' own controls "
             "(cavities[].pressure or added_volume) from 0 to full; give targets in later "
             "states");
    if (i == 0 && node[i].IsMap() && node[i]["move"])
      r.fail(child_key(key, "move"), node[i]["move"],
             "not allowed in the first state: it ramps the boundary's own values "
             "(boundary[].value) from 0 to full; move a group in later states");
    StateConfig s;
    read_keys(r, node[i], key, state_keys(), s, c);
    for (size_t j = 0; j < i; ++j)
      if (states[j].name == s.name)
        r.fail(child_key(key, "name"), node[i]["name"],
               "duplicate state name '" + s.name + "' (also in " + item_key("states", j) + ")");
    states.push_back(s);
  }
  if (c.time.type == TimeType::dynamic) check_state_times(r, node, states, c.time);
  return states;
}

std::vector<int64_t> state_time_steps(const std::vector<StateConfig>& states, double dt) {
  std::vector<int64_t> steps;
  for (size_t k = 0; k < states.size(); ++k) {
    const double t = states[k].time.value_or(0.0);
    if (k > 0 && t == states[k - 1].time.value_or(0.0))
      steps.push_back(steps.back() + 1);
    else
      steps.push_back(std::llround(t / dt));
  }
  if (steps.empty()) steps.push_back(0);
  return steps;
}

}  // namespace hs
