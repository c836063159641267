// parse_control: the end effectors of a soft robot, the cavities that actuate it and
// the targets its effectors are driven to (docs/decks.md, "control"; docs/control.md).
#include "deck/control_section.hpp"

#include <algorithm>
#include <string>
#include <vector>

#include "deck/cavity_sections.hpp"
#include "deck/section_keys.hpp"

namespace hs {
namespace {

EffectorConfig parse_effector(const DeckReader& r, const YAML::Node& node, const std::string& key,
                              const Config& c) {
  EffectorConfig e;
  read_keys(r, node, key, effector_keys(), e, c);
  // A mesh node, a material point inside an element, an obstacle's contact force or the
  // contact force between two surfaces: one.
  if (!node["point"] + !node["position"] + !node["obstacle"] + !node["between"] != 3)
    r.fail(key, node,
           "give exactly one of point (a point group with one node), position (a material "
           "point, in reference coordinates), obstacle (the contact force on it) or between "
           "(the contact force one surface exerts on another)");
  if (node["between"]) {
    const std::string bkey = child_key(key, "between");
    if (e.between.size() != 2)
      r.fail(bkey, node["between"],
             "names two surfaces, [A, B]: the force A exerts on B (" +
                 std::to_string(e.between.size()) + " given)");
    if (!c.contact.self)
      r.fail(bkey, node["between"],
             "needs contact.self: true (the force between surfaces that touch each other)");
    for (size_t i = 0; i < e.between.size(); ++i)
      if (!contains(c.contact.surfaces, e.between[i]))
        r.fail(item_key(bkey, i), node["between"][i],
               "'" + e.between[i] + "' is not one of contact.surfaces (" +
                   join(c.contact.surfaces) + ")");
    if (e.between.size() == 2 && e.between[0] == e.between[1])
      r.fail(bkey, node["between"], "names '" + e.between[0] + "' twice: give two surfaces");
  }
  if (!e.obstacle.empty()) {
    std::vector<std::string> names;
    for (const auto& o : c.obstacles) names.push_back(o.name);
    if (names.empty())
      r.fail(child_key(key, "obstacle"), node["obstacle"],
             "the deck has no obstacles (a contact-force effector needs one)");
    if (std::find(names.begin(), names.end(), e.obstacle) == names.end())
      r.fail(child_key(key, "obstacle"), node["obstacle"],
             "no obstacle named '" + e.obstacle + "' (did you mean '" + nearest(e.obstacle, names) +
                 "'? obstacles: " + join(names) + ")");
  }
  if (!e.surfaces.empty() && e.obstacle.empty())
    r.fail(child_key(key, "surfaces"), node["surfaces"], "needs obstacle (a contact force)");
  const auto& contact = c.contact.surfaces;
  for (size_t i = 0; i < e.surfaces.size(); ++i)
    if (std::find(contact.begin(), contact.end(), e.surfaces[i]) == contact.end())
      r.fail(item_key(child_key(key, "surfaces"), i), node["surfaces"][i],
             "'" + e.surfaces[i] + "' is not one of contact.surfaces (" + join(contact) + ")");
  return e;
}

std::vector<EffectorConfig> parse_effectors(const DeckReader& r, const YAML::Node& node,
                                            const std::string& key, const Config& c) {
  r.check_list(node, key);
  require(node.size() > 0, r, node, key, "at least one effector is required");
  std::vector<EffectorConfig> effectors;
  for (size_t i = 0; i < node.size(); ++i) {
    const std::string ekey = item_key(key, i);
    effectors.push_back(parse_effector(r, node[i], ekey, c));
    if (effectors[i].name == "move")
      r.fail(child_key(ekey, "name"), node[i]["name"],
             "'move' is a target set's key (the boundary groups it moves): name the effector "
             "otherwise");
    for (size_t j = 0; j < i; ++j)
      if (effectors[j].name == effectors[i].name)
        r.fail(child_key(ekey, "name"), node[i]["name"],
               "duplicate effector name '" + effectors[i].name + "' (also in " + item_key(key, j) +
                   ")");
  }
  return effectors;
}

// The lower bound `low_name` must not exceed the upper one `high_name` (unset: unbounded).
void check_bounds(const DeckReader& r, const YAML::Node& node, const std::string& key,
                  const std::string& low_name, const std::string& high_name, double low,
                  double high) {
  if (low > high)
    r.fail(child_key(key, low_name), node[low_name],
           "is " + format_number(low) + " but " + high_name + " is " + format_number(high) +
               " (the lower bound must not exceed the upper one)");
}

// A cable actuator: bounds on its tension (N) and its pull (its shortening, m).
ActuatorConfig parse_cable_actuator(const DeckReader& r, const YAML::Node& node,
                                    const std::string& key, const Config& c) {
  ActuatorConfig a;
  a.min_multiplier = 0;  // a cable cannot push
  read_keys(r, node, key, cable_actuator_keys(), a, c);
  check_bounds(r, node, key, "min_force", "max_force", a.min_multiplier, a.max_multiplier);
  check_bounds(r, node, key, "min_pull", "max_pull", a.min_measure_change, a.max_measure_change);
  return a;
}

ActuatorConfig parse_actuator(const DeckReader& r, const YAML::Node& node, const std::string& key,
                              const Config& c) {
  if (node.IsMap() && node["cable"]) {
    if (node["cavity"])
      r.fail(child_key(key, "cable"), node["cable"], "give one of cavity and cable, not both");
    return parse_cable_actuator(r, node, key, c);
  }
  ActuatorConfig a;
  read_keys(r, node, key, cavity_actuator_keys(), a, c);
  check_bounds(r, node, key, "min_pressure", "max_pressure", a.min_multiplier, a.max_multiplier);
  check_bounds(r, node, key, "min_volume_growth", "max_volume_growth", a.min_measure_change,
               a.max_measure_change);
  return a;
}

std::vector<ActuatorConfig> parse_actuators(const DeckReader& r, const YAML::Node& node,
                                            const std::string& key, const Config& c) {
  r.check_list(node, key);
  require(node.size() > 0, r, node, key, "at least one actuator is required");
  std::vector<ActuatorConfig> actuators;
  for (size_t i = 0; i < node.size(); ++i) {
    const std::string akey = item_key(key, i);
    actuators.push_back(parse_actuator(r, node[i], akey, c));
    const char* what = node[i]["cable"] ? "cable" : "cavity";
    for (size_t j = 0; j < i; ++j)
      if (actuators[j].constraint == actuators[i].constraint)
        r.fail(child_key(akey, what), node[i][what],
               std::string("duplicate actuator ") + what + " '" + actuators[i].constraint +
                   "' (also in " + item_key(key, j) + ")");
  }
  return actuators;
}

// The target sets, in order: each a map effector name -> [x, y, z], kept in the deck's order,
// and its boundary groups' translations (the key `move`) into `moves`.
std::vector<std::vector<ControlTarget>> parse_control_targets(
    const DeckReader& r, const YAML::Node& node, const std::string& key,
    const std::vector<EffectorConfig>& effectors, const Config& c,
    std::vector<std::map<std::string, std::array<double, 3>>>& moves) {
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
    moves.emplace_back();
    for (const auto& entry : node[i]) {
      const std::string name = entry.first.Scalar(), tkey = child_key(skey, name);
      if (name == "move") {
        moves.back() = parse_moves(r, entry.second, tkey, c);
        continue;
      }
      for (const auto& t : set)
        if (t.effector == name) r.fail(tkey, entry.first, "duplicate key");
      if (!contains(names, name))
        r.fail(tkey, entry.first,
               "not an effector (did you mean '" + nearest(name, names) +
                   "'? effectors: " + join(names) + ")");
      set.push_back(ControlTarget{name, r.vector3(entry.second, tkey)});
    }
    require(!set.empty(), r, node[i], skey,
            "a target set names at least one effector besides its move (effectors: " + join(names) +
                ")");
    sets.push_back(set);
  }
  return sets;
}

// An actuator's bound, printed only where the deck set it: an unset bound is no bound (and
// 1e300 would read as a bound the deck never gave).
DeckKey<ActuatorConfig> bound_key(std::string name, double ActuatorConfig::*member, Limit limit,
                                  std::string meaning) {
  return number_key(std::move(name), member, std::move(limit), std::move(meaning))
      .defaults_to("none")
      .printed_when(
          [member](const ActuatorConfig& a) { return a.*member != ActuatorConfig{}.*member; });
}

// The actuator's constraint: a declared cavity of `kind` ... or cable, by name.
DeckKey<ActuatorConfig> constraint_key(std::string name, std::string meaning, bool cable) {
  return custom_key<ActuatorConfig>(
             std::move(name), "name", "required", std::move(meaning),
             [cable](const DeckReader& r, const YAML::Node& n, const std::string& key,
                     ActuatorConfig& a, const Config& c) {
               a.constraint = r.text(n, key);
               std::vector<std::string> names;
               if (cable)
                 for (const auto& cable : c.cables) names.push_back(cable.name);
               else
                 for (const auto& cavity : c.cavities) names.push_back(cavity.group);
               const std::string what = cable ? "cable" : "cavity";
               const auto found = std::find(names.begin(), names.end(), a.constraint);
               if (found == names.end())
                 r.fail(key, n,
                        names.empty()
                            ? "not a declared " + what + " (the deck has no " +
                                  (cable ? "cables" : "cavities") + " section)"
                            : "not a declared " + what + " (did you mean '" +
                                  nearest(a.constraint, names) + "'? " +
                                  (cable ? "cables" : "cavities") + ": " + join(names) + ")");
               if (cable) return;
               const CavityKind kind = c.cavities[found - names.begin()].kind;
               if (!is_actuated(kind))
                 r.fail(key, n,
                        "cavity '" + a.constraint + "' is " + name_of(kCavityKindNames, kind) +
                            ": only pneumatic and hydraulic cavities are actuated, so control "
                            "cannot drive it");
             },
             [](YAML::Emitter& out, const ActuatorConfig& a, const Config&) {
               out << a.constraint;
             })
      .needed();
}

}  // namespace

const KeyTable<EffectorConfig>& effector_keys() {
  static const KeyTable<EffectorConfig> keys = {
      text_key("name", &EffectorConfig::name, "name",
               "unique across effectors; the target sets name it")
          .needed(),
      text_key("point", &EffectorConfig::point, "name",
               "a physical point group of the mesh with exactly one node (checked once the mesh "
               "is loaded), e.g. `effector` of `meshes/finger.geo`; the effector is that node")
          .defaults_to("required (or `position`, `obstacle`, `between`)")
          .printed_when([](const EffectorConfig& e) { return !e.point.empty(); }),
      custom_key<EffectorConfig>(
          "position", "3 numbers", "required (or `point`, `obstacle`, `between`)",
          "a point of the undeformed body, in reference coordinates (m); the solver finds the "
          "element that holds it (a point outside the mesh is an error then). Give exactly one "
          "of `point`, `position`, `obstacle` and `between`.",
          [](const DeckReader& r, const YAML::Node& n, const std::string& key, EffectorConfig& e,
             const Config&) { e.position = r.vector3(n, key); },
          [](YAML::Emitter& out, const EffectorConfig& e, const Config&) {
            write_numbers(out, e.position.data(), 3);
          })
          .printed_when([](const EffectorConfig& e) {
            return e.point.empty() && e.obstacle.empty() && e.between.empty();
          }),
      text_key("obstacle", &EffectorConfig::obstacle, "name",
               "an obstacle of `obstacles` (docs/contact.md): the effector is then the contact "
               "force the body exerts on it (N, summary.json's contact force), and its targets "
               "are forces, e.g. `{press: [0, 0, -0.2]}` to press it down with 0.2 N. Its row "
               "in the controller is that force's derivative at each step's free "
               "configuration (through the compliance, which includes the barrier)")
          .defaults_to("required (or `point`, `position`, `between`)")
          .printed_when([](const EffectorConfig& e) { return !e.obstacle.empty(); }),
      names_key<EffectorConfig>(
          "between", &EffectorConfig::between, "required (or `point`, `position`, `obstacle`)",
          "two of `contact.surfaces`, `[A, B]`, with `contact.self` (docs/contact.md): the "
          "effector is then the contact force A exerts on B through their pairs (N; the "
          "barrier's, not friction's), e.g. `[skin_left, object_skin]` for one finger's grasp "
          "on a body of the same mesh. A face in two of `contact.surfaces` counts as the first "
          "listed. Its rows are the force's derivative at each step's free configuration, as "
          "`obstacle`'s")
          .printed_when([](const EffectorConfig& e) { return !e.between.empty(); }),
      names_key<EffectorConfig>(
          "surfaces", &EffectorConfig::surfaces, "all of `contact.surfaces`",
          "with `obstacle`: the force of these contact surfaces only (each one of "
          "`contact.surfaces`), e.g. one finger's skin, so that each finger of a gripper has its "
          "own grasp force; where the surfaces share nodes each node counts once")
          .printed_when([](const EffectorConfig& e) { return !e.surfaces.empty(); }),
      custom_key<EffectorConfig>(
          "directions", "list of `x`, `y`, `z`", "`[x, y, z]`",
          "the components of the effector's position (or force) that are steered; the others are "
          "free "
          "(non-empty, no repeats)",
          [](const DeckReader& r, const YAML::Node& n, const std::string& key, EffectorConfig& e,
             const Config&) { e.directions = read_axes(r, n, key, "direction"); },
          [](YAML::Emitter& out, const EffectorConfig& e, const Config&) {
            write_axes(out, e.directions);
          }),
      number_key("weight", &EffectorConfig::weight, above(0),
                 "the weight of this effector's squared error"),
  };
  return keys;
}

const KeyTable<ActuatorConfig>& cavity_actuator_keys() {
  static const KeyTable<ActuatorConfig> keys = {
      constraint_key("cavity",
                     "a cavity of the `cavities` section of kind `pneumatic` or `hydraulic` "
                     "(the other kinds are not actuated); at most one actuator per cavity",
                     false),
      bound_key("min_pressure", &ActuatorConfig::min_multiplier, any_number(),
                "lower bound on the cavity's gauge pressure (Pa); at most `max_pressure` (equal "
                "bounds hold the pressure)"),
      bound_key("max_pressure", &ActuatorConfig::max_multiplier, any_number(),
                "upper bound on the cavity's gauge pressure (Pa)"),
      bound_key("min_volume_growth", &ActuatorConfig::min_measure_change, any_number(),
                "lower bound on the cavity's volume minus its volume at the rest state (m³); at "
                "most `max_volume_growth`"),
      bound_key("max_volume_growth", &ActuatorConfig::max_measure_change, any_number(),
                "upper bound on the cavity's volume minus its volume at the rest state (m³)"),
      bound_key("max_pressure_change", &ActuatorConfig::max_multiplier_step, above(0),
                "the most the pressure may change in one control step (Pa)"),
  };
  return keys;
}

const KeyTable<ActuatorConfig>& cable_actuator_keys() {
  static const KeyTable<ActuatorConfig> keys = {
      constraint_key("cable",
                     "a cable of the `cables` section; at most one actuator per cable (instead "
                     "of `cavity`)",
                     true),
      // Printed always: a cable actuator's lower bound is 0 unless the deck sets another.
      number_key("min_force", &ActuatorConfig::min_multiplier,
                 at_least(0, "a cable pulls, it cannot push"),
                 "lower bound on the tension (N); at most `max_force`")
          .defaults_to("0"),
      bound_key("max_force", &ActuatorConfig::max_multiplier, any_number(),
                "upper bound on the tension (N)"),
      bound_key("min_pull", &ActuatorConfig::min_measure_change, any_number(),
                "lower bound on the pull: the cable's shortening since the rest state (m); at "
                "most `max_pull`"),
      bound_key("max_pull", &ActuatorConfig::max_measure_change, any_number(),
                "upper bound on the pull (m)"),
      bound_key("max_force_change", &ActuatorConfig::max_multiplier_step, above(0),
                "the most the tension may change in one control step (N)"),
  };
  return keys;
}

const KeyTable<ControlConfig>& control_keys() {
  static const KeyTable<ControlConfig> keys = {
      custom_key<ControlConfig>(
          "effectors", "list", "required", "at least one; the keys below",
          [](const DeckReader& r, const YAML::Node& n, const std::string& key, ControlConfig& k,
             const Config& c) { k.effectors = parse_effectors(r, n, key, c); },
          [](YAML::Emitter& out, const ControlConfig& k, const Config& c) {
            out << YAML::BeginSeq;
            for (const auto& e : k.effectors) {
              out << YAML::BeginMap;
              write_keys(out, effector_keys(), e, c);
              out << YAML::EndMap;
            }
            out << YAML::EndSeq;
          })
          .needed(),
      custom_key<ControlConfig>(
          "actuators", "list", "required", "at least one; the keys below",
          [](const DeckReader& r, const YAML::Node& n, const std::string& key, ControlConfig& k,
             const Config& c) { k.actuators = parse_actuators(r, n, key, c); },
          [](YAML::Emitter& out, const ControlConfig& k, const Config& c) {
            out << YAML::BeginSeq;
            for (const auto& a : k.actuators) {
              const bool cable =
                  std::any_of(c.cables.begin(), c.cables.end(),
                              [&](const CableConfig& cable) { return cable.name == a.constraint; });
              out << YAML::BeginMap;
              write_keys(out, cable ? cable_actuator_keys() : cavity_actuator_keys(), a, c);
              out << YAML::EndMap;
            }
            out << YAML::EndSeq;
          })
          .needed(),
      custom_key<ControlConfig>(
          "targets", "list of maps effector: 3 numbers", "none",
          "target sets, reached one after the other: each maps effector names to the position "
          "(m) the effector should reach, e.g. `{tip: [0.09, 0, -0.01]}` (a contact-force "
          "effector's: the force, N). A set names at least "
          "one effector, each at most once. A set's `move: {group: [dx, dy, dz]}` translates "
          "boundary groups over its steps as a state's `move` does (a palm that rises while the "
          "fingers keep their grasp force; not with `free_solve: one_step`, `reduced_model` or "
          "output.checkpoint). Without `targets` the run has none from the deck: "
          "`--targets -` on the command line reads them from standard input (docs/control.md); "
          "that switch is not a deck key.",
          [](const DeckReader& r, const YAML::Node& n, const std::string& key, ControlConfig& k,
             const Config& c) {
            k.moves.clear();
            k.targets = parse_control_targets(r, n, key, k.effectors, c, k.moves);
          },
          [](YAML::Emitter& out, const ControlConfig& k, const Config&) {
            out << YAML::BeginSeq;
            for (size_t i = 0; i < k.targets.size(); ++i) {
              out << YAML::Flow << YAML::BeginMap;
              for (const auto& t : k.targets[i]) {
                out << YAML::Key << t.effector << YAML::Value;
                write_numbers(out, t.position.data(), 3);
              }
              if (i < k.moves.size() && !k.moves[i].empty()) {
                out << YAML::Key << "move" << YAML::Value << YAML::BeginMap;
                for (const auto& [group, by] : k.moves[i]) {
                  out << YAML::Key << group << YAML::Value;
                  write_numbers(out, by.data(), 3);
                }
                out << YAML::EndMap;
              }
              out << YAML::EndMap;
            }
            out << YAML::EndSeq;
          })
          // Only when the deck gave targets: an empty list is not a valid deck.
          .printed_when([](const ControlConfig& k) { return !k.targets.empty(); }),
      integer_key("steps_per_target", &ControlConfig::steps_per_target, at_least(1),
                  "control steps spent on each target set"),
      number_key("regularization", &ControlConfig::regularization, at_least(0),
                 "weight of the squared pressure changes against the effector error (its "
                 "scaling: docs/control.md); 0 leaves the pressure changes unpenalised"),
      bool_key("newton_finish", &ControlConfig::newton_finish,
               "end every control step with a Newton solve of the equilibrium at the step's new "
               "pressures"),
      enum_key("free_solve", &ControlConfig::free_solve, kFreeSolveNames,
               "`newton`: the free configuration of each step is converged by Newton at the held "
               "pressures, and each target set's reported position is the equilibrium at its "
               "final pressures; `one_step`: the paper's real-time step, one linearisation (one "
               "assembly, one factorization) for the free motion and the compliance together, "
               "the reported position the step's prediction (docs/control.md)"),
      enum_key("contact_forces", &ControlConfig::contact_forces, kContactForcesNames,
               "`free_step`: contact with the obstacles is the barrier's, solved inside each free "
               "configuration, and the compliance includes it; `qp`: the obstacles' normal forces "
               "on the contact nodes are unknowns of the QP beside the pressures, under "
               "complementarity with their gaps (each force >= 0, each gap >= 0, their product "
               "0), and the free configuration holds them as loads. `qp` needs obstacles without "
               "friction, free_solve newton, and no contact.self, reduced_model, checkpoint or "
               "target set's move "
               "(docs/control.md, \"Contact forces in the QP\")")
          .printed_when(
              [](const ControlConfig& k) { return k.contact_forces != ContactForces::free_step; }),
      integer_key("refactor_every", &ControlConfig::refactor_every, at_least(1),
                  "`one_step` only: factorize the tangent every N steps and reuse it in between "
                  "(a modified-Newton free step on the fresh residual, the compliance of up to "
                  "N − 1 steps ago)"),
      number_key(
          "one_step_tolerance", &ControlConfig::one_step_tolerance, at_least(0),
          "`one_step` with `refactor_every: 1` (m): each step ends with a free step from its "
          "correction (one residual, one solve with the step's factorization), and while "
          "that free step moves the targeted effectors by more than this the step is "
          "taken again from the correction with a fresh factorization (at most 4 times); the "
          "answers' `free_step_m` is that free step, a lower bound of their distance from "
          "equilibrium (within 0.1 mm on the finger decks). 0: the single linearisation of "
          "the paper (docs/control.md)"),
      bool_key("check_equilibrium", &ControlConfig::check_equilibrium,
               "`one_step` or `reduced_model` only: after each target set, also solve the full "
               "model for the equilibrium at its pressures (on a copy, outside the step times) "
               "and report it as `equilibrium`, `equilibrium_error_m`"),
      integer_key("check_every", &ControlConfig::check_every, at_least(1),
                  "with `check_equilibrium`: the check on the first target set and every N-th "
                  "after it (sets 1, N + 1, 2 N + 1, ...; the others' answers have no "
                  "`equilibrium`): a full solve costs many reduced or one_step answers")
          .printed_when([](const ControlConfig& k) { return k.check_equilibrium; }),
      text_key("reduced_model", &ControlConfig::reduced_model, "file",
               "a reduced-order model written by `hydrosoft reduce` for this deck's mesh and "
               "physics (a path from the working directory): the control steps are solved in "
               "its reduced space (docs/reduced_models.md); one rank")
          .printed_when([](const ControlConfig& k) { return !k.reduced_model.empty(); }),
      bool_key("error_indicator", &ControlConfig::error_indicator,
               "with `reduced_model`: each answer also estimates its error from the full "
               "model's residual at the answer, weighted by the effectors' influence functions "
               "at the nearest training sample and calibrated by the training, and states the "
               "larger of that and the held-back error (one full residual an answer; "
               "docs/reduced_models.md, \"Each answer's error\")")
          .printed_when([](const ControlConfig& k) { return !k.reduced_model.empty(); }),
      integer_key("factor_threads", &ControlConfig::factor_threads, within(0, 64),
                  "`one_step` only: threads (on rank 0) that factor the tangent in the "
                  "background while the loop steps on; each step then corrects with the newest "
                  "factorization it has (GMRES on the current tangent, preconditioned by it) and "
                  "factors in line only when it has none or one failed (docs/control.md, "
                  "\"Factorizations in the background\"). 1 on a 2-core machine with 1 rank"),
  };
  return keys;
}

ControlConfig parse_control(const DeckReader& r, const YAML::Node& node, const Config& c) {
  const std::string key = "control";
  if (node.IsMap() && node["targets_from_stdin"])
    r.fail(child_key(key, "targets_from_stdin"), node["targets_from_stdin"],
           "not a deck key: the command line sets it (--targets -)");
  ControlConfig control;
  read_keys(r, node, key, control_keys(), control, c);
  // Kept where Newton is the free solve as long as they change nothing (printed, so that the
  // printout stays the restart fingerprint of such decks).
  if (control.free_solve != FreeSolve::one_step) {
    require(control.refactor_every == 1, r, node["refactor_every"], "control.refactor_every",
            "needs free_solve: one_step (Newton refactors every step)");
    require(control.factor_threads == 0, r, node["factor_threads"], "control.factor_threads",
            "needs free_solve: one_step");
    require(control.one_step_tolerance == ControlConfig{}.one_step_tolerance, r,
            node["one_step_tolerance"], "control.one_step_tolerance",
            "needs free_solve: one_step (Newton converges every free configuration)");
  }
  require(!control.error_indicator || !control.reduced_model.empty(), r, node["error_indicator"],
          "control.error_indicator", "needs reduced_model");
  require(control.check_every == 1 || control.check_equilibrium, r, node["check_every"],
          "control.check_every", "needs check_equilibrium: true");
  return control;
}

}  // namespace hs
