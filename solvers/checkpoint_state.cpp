// The checks of a checkpoint's state before a restart uses it (check_checkpoint_state). The
// state is JSON text in the file, which anyone can edit: every field the stepping reads back
// is checked here for its kind and its range against the deck, so that a tampered or damaged
// file is refused with one line naming the file and the field, before any work, and never
// reaches the stepping as a step past the end, a negative count or a JSON library's
// exception.
#include <algorithm>
#include <charconv>
#include <climits>
#include <cmath>

#include "common/error.hpp"
#include "deck/cavity_sections.hpp"
#include "deck/config_fingerprint.hpp"
#include "solvers/checkpoint.hpp"
#include "solvers/stepping.hpp"
#include "solvers/stepping/state_plan.hpp"

namespace hs {
namespace {

using nlohmann::json;

// Reads fields of the state, each named by its dotted path ("position.stepper.tau") in the
// message of the InputError that a missing or out-of-range one throws.
class Fields {
 public:
  explicit Fields(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const std::string& key, const std::string& reason) const {
    throw InputError("--restart: " + file_ + ": " + key + ": " + reason);
  }

  const json& at(const json& object, const std::string& parent, const std::string& name) const {
    const std::string key = parent.empty() ? name : parent + "." + name;
    if (!object.is_object()) fail(parent, "must be an object, got " + shown(object));
    const auto it = object.find(name);
    if (it == object.end()) fail(key, "missing");
    return *it;
  }

  int64_t integer(const json& value, const std::string& key, int64_t low, int64_t high,
                  const std::string& meaning = "") const {
    const std::string range = "must be an integer from " + std::to_string(low) + " to " +
                              std::to_string(high) + (meaning.empty() ? "" : " (" + meaning + ")");
    // JSON reads a number without a sign as unsigned: 2^64 - 1 must not pass as -1.
    bool outside = !value.is_number_integer();
    if (!outside && value.is_number_unsigned()) {
      const uint64_t u = value.get<uint64_t>();
      outside = u > static_cast<uint64_t>(high) || static_cast<int64_t>(u) < low;
    } else if (!outside) {
      outside = value.get<int64_t>() < low || value.get<int64_t>() > high;
    }
    if (outside) fail(key, range + ", got " + shown(value));
    return value.get<int64_t>();
  }
  int64_t integer(const json& object, const std::string& parent, const std::string& name,
                  int64_t low, int64_t high, const std::string& meaning = "") const {
    return integer(at(object, parent, name), key(parent, name), low, high, meaning);
  }

  int64_t count(const json& object, const std::string& parent, const std::string& name) const {
    return integer(object, parent, name, 0, INT_MAX);
  }

  double number(const json& value, const std::string& key) const {
    if (!value.is_number() || !std::isfinite(value.get<double>()))
      fail(key, "must be a finite number, got " + shown(value));
    return value.get<double>();
  }
  double number(const json& object, const std::string& parent, const std::string& name) const {
    return number(at(object, parent, name), key(parent, name));
  }

  bool boolean(const json& object, const std::string& parent, const std::string& name) const {
    const json& value = at(object, parent, name);
    if (!value.is_boolean()) fail(key(parent, name), "must be true or false, got " + shown(value));
    return value.get<bool>();
  }

  std::string text(const json& object, const std::string& parent, const std::string& name) const {
    const json& value = at(object, parent, name);
    if (!value.is_string()) fail(key(parent, name), "must be a string, got " + shown(value));
    return value.get<std::string>();
  }

  // An array of `size` entries (any size when negative).
  const json& array(const json& object, const std::string& parent, const std::string& name,
                    int64_t size = -1, const std::string& meaning = "") const {
    const json& value = at(object, parent, name);
    if (!value.is_array()) fail(key(parent, name), "must be a list, got " + shown(value));
    if (size >= 0 && static_cast<int64_t>(value.size()) != size)
      fail(key(parent, name), "must have " + std::to_string(size) + " entries" +
                                  (meaning.empty() ? "" : " (" + meaning + ")") + ", has " +
                                  std::to_string(value.size()));
    return value;
  }

  void numbers(const json& object, const std::string& parent, const std::string& name,
               int64_t size = -1, const std::string& meaning = "") const {
    const json& list = array(object, parent, name, size, meaning);
    for (size_t i = 0; i < list.size(); ++i)
      number(list[i], key(parent, name) + "[" + std::to_string(i) + "]");
  }

  void counts(const json& object, const std::string& parent, const std::string& name) const {
    const json& list = array(object, parent, name);
    for (size_t i = 0; i < list.size(); ++i)
      integer(list[i], key(parent, name) + "[" + std::to_string(i) + "]", 0, INT_MAX);
  }

  // An array of objects (summary entries: the stepping adds to them, reads nothing in them).
  void objects(const json& object, const std::string& parent, const std::string& name,
               int64_t size = -1, const std::string& meaning = "") const {
    const json& list = array(object, parent, name, size, meaning);
    for (size_t i = 0; i < list.size(); ++i)
      if (!list[i].is_object())
        fail(key(parent, name) + "[" + std::to_string(i) + "]",
             "must be an object, got " + shown(list[i]));
  }

  static std::string key(const std::string& parent, const std::string& name) {
    return parent.empty() ? name : parent + "." + name;
  }

 private:
  // A value as the message quotes it: its JSON, cut at 40 characters.
  static std::string shown(const json& value) {
    const std::string text = value.dump(-1, ' ', true, json::error_handler_t::replace);
    return text.size() <= 40 ? text : text.substr(0, 40) + "...";
  }

  std::string file_;
};

bool near(double a, double b) { return std::abs(a - b) <= 1e-12 * std::max(1.0, std::abs(b)); }

std::string number_text(double x) {
  char buffer[32];
  return std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, x).ptr);
}

// The increments of each state, as the state stepping plans them.
std::vector<int64_t> state_increments(const Config& config) {
  std::vector<int64_t> increments;
  for (const StatePlan& plan : plan_states(config))
    increments.push_back(static_cast<int64_t>(plan.taus.size()));
  return increments;
}

// The constraints' names in the order of the ConstraintSet: the cavities, then the cables.
std::vector<std::string> constraint_names(const Config& config) {
  std::vector<std::string> names;
  for (const auto& cavity : config.cavities) names.push_back(cavity.group);
  for (const auto& cable : config.cables) names.push_back(cable.name);
  return names;
}

void check_constraints(const Fields& f, const json& object, const std::string& parent,
                       const std::string& name, const Config& config) {
  const std::vector<std::string> names = constraint_names(config);
  const json& list = f.array(object, parent, name, static_cast<int64_t>(names.size()),
                             "this deck's cavities and cables");
  for (size_t k = 0; k < list.size(); ++k) {
    const std::string entry = Fields::key(parent, name) + "[" + std::to_string(k) + "]";
    const std::string written = f.text(list[k], entry, "name");
    if (written != names[k])
      f.fail(entry + ".name", "is '" + written + "', this deck's is '" + names[k] + "'");
    for (const char* value : {"lambda", "target", "measure", "rest_measure"})
      f.number(list[k], entry, value);
    f.integer(list[k], entry, "control", 0, 2, "multiplier, measure or own law");
  }
}

// `last` says whether the position is the run's last step; it must agree with the step.
void check_last(const Fields& f, const json& p, bool is_last) {
  if (f.boolean(p, "position", "last") != is_last)
    f.fail("position.last",
           std::string("must be ") + (is_last ? "true" : "false") + " at this step of this deck");
}

void check_static(const Fields& f, const json& p, const Config& config) {
  const std::vector<double> schedule = load_schedule(config.time);
  const int64_t n = static_cast<int64_t>(schedule.size());
  const int64_t step = f.integer(p, "position", "step", 1, n, "this deck's load steps");
  check_last(f, p, step == n);
  const double load = f.number(p, "position", "load_factor");
  if (!near(load, schedule[step - 1]))
    f.fail("position.load_factor", "must be step " + std::to_string(step) + "'s, " +
                                       number_text(schedule[step - 1]) + ", got " +
                                       number_text(load));
  const double previous = f.number(p, "position", "previous_load_factor");
  const double before = step > 1 ? schedule[step - 2] : 0.0;
  if (f.boolean(p, "position", "has_previous") &&
      (previous < std::min(before, load) || previous > std::max(before, load)))
    f.fail("position.previous_load_factor",
           "must lie between the load factors of steps " + std::to_string(step - 1) + " and " +
               std::to_string(step) + ", got " + number_text(previous));
  f.objects(p, "position", "verification");
  if (static_cast<int64_t>(p.at("verification").size()) > step)
    f.fail("position.verification",
           "has more entries than the " + std::to_string(step) + " steps done");
}

void check_dynamic(const Fields& f, const json& p, const Config& config) {
  const int64_t n = static_cast<int64_t>(std::ceil(config.time.end_time / config.time.dt - 1e-9));
  const int64_t step = f.integer(p, "position", "step", 1, n, "this deck's time steps");
  check_last(f, p, step == n);
  const double dt = f.number(p, "position", "dt");
  if (!near(dt, config.time.dt))
    f.fail("position.dt", "must be this deck's time.dt, " + number_text(config.time.dt) + ", got " +
                              number_text(dt));
  const double time = f.number(p, "position", "time");
  if (std::abs(time - step * config.time.dt) > 1e-9 * std::max(1.0, step * config.time.dt))
    f.fail("position.time", "must be step " + std::to_string(step) + " times time.dt, " +
                                number_text(step * config.time.dt) + ", got " + number_text(time));
}

// A dynamic run with constraints: its time step, the state that step ramps towards (the first
// whose time step is not before it, else the last), that state's ramps, the constraints, the
// states done and the work so far.
void check_dynamic_states(const Fields& f, const json& p, const Config& config) {
  check_dynamic(f, p, config);
  const int64_t step = p.at("step").get<int64_t>();
  const std::vector<int64_t> ends = state_time_steps(config.states, config.time.dt);
  const int64_t states = static_cast<int64_t>(ends.size());
  int64_t k = 0;
  while (k + 1 < states && step > ends[k]) ++k;
  if (f.integer(p, "position", "state", 0, states - 1, "this deck's states") != k)
    f.fail("position.state", "must be " + std::to_string(k) + ", the state of time step " +
                                 std::to_string(step) + " in this deck");
  const int64_t constraints = static_cast<int64_t>(constraint_names(config).size());
  const json& ramps =
      f.array(p, "position", "ramps", constraints, "this deck's cavities and cables");
  for (size_t c = 0; c < ramps.size(); ++c) {
    const std::string entry = "position.ramps[" + std::to_string(c) + "]";
    f.boolean(ramps[c], entry, "active");
    f.integer(ramps[c], entry, "control", 0, 2, "multiplier, measure or own law");
    f.number(ramps[c], entry, "from");
    f.number(ramps[c], entry, "to");
  }
  check_constraints(f, p, "position", "constraints", config);
  f.objects(p, "position", "states");
  if (static_cast<int64_t>(p.at("states").size()) > k + 1)
    f.fail("position.states", "has more entries than the " + std::to_string(k + 1) +
                                  " states begun by time step " + std::to_string(step));
  f.number(p, "position", "work_loads");
  f.numbers(p, "position", "work", constraints, "this deck's cavities and cables");
}

void check_states(const Fields& f, const json& p, const Config& config) {
  const std::vector<int64_t> increments = state_increments(config);
  const int64_t states = static_cast<int64_t>(increments.size());
  const int64_t k = f.integer(p, "position", "state", 0, states - 1, "this deck's states");
  const int64_t i =
      f.integer(p, "position", "increment", 1, increments[k], "the increments of its state");
  check_last(f, p, k + 1 == states && i == increments[k]);
  f.number(p, "position", "state_time");
  const int64_t constraints = static_cast<int64_t>(constraint_names(config).size());
  const json& stepper = f.at(p, "position", "stepper");
  const json& ramps =
      f.array(stepper, "position.stepper", "ramps", constraints, "this deck's cavities and cables");
  for (size_t c = 0; c < ramps.size(); ++c) {
    const std::string entry = "position.stepper.ramps[" + std::to_string(c) + "]";
    f.boolean(ramps[c], entry, "active");
    f.integer(ramps[c], entry, "control", 0, 2, "multiplier, measure or own law");
    f.number(ramps[c], entry, "from");
    f.number(ramps[c], entry, "to");
  }
  f.number(stepper, "position.stepper", "tau");
  f.number(stepper, "position.stepper", "tau_last");
  f.boolean(stepper, "position.stepper", "has_last");
  const json& lambdas = f.array(stepper, "position.stepper", "lambda_last");
  if (!lambdas.empty())
    f.numbers(stepper, "position.stepper", "lambda_last", constraints,
              "this deck's cavities and cables");
  // The first state's change of each measure by an exact load (load_model_error.hpp): none, or
  // one per constraint; absent from checkpoints written before it.
  if (stepper.contains("rest_change") &&
      !f.array(stepper, "position.stepper", "rest_change").empty())
    f.numbers(stepper, "position.stepper", "rest_change", constraints,
              "this deck's cavities and cables");
  check_constraints(f, p, "position", "constraints", config);
  f.objects(p, "position", "states", k, "the states done before");
}

void check_control(const Fields& f, const json& p, const Config& config) {
  const int64_t sets = static_cast<int64_t>(config.control->targets.size());
  const int64_t done = f.integer(p, "position", "target_set", 1, std::max<int64_t>(sets, 1),
                                 "this deck's target sets");
  check_last(f, p, done == sets);
  check_constraints(f, p, "position", "constraints", config);
  f.objects(p, "position", "states", static_cast<int64_t>(state_increments(config).size()),
            "this deck's states");
  const std::string c = "position.controller";
  const json& controller = f.at(p, "position", "controller");
  const int64_t actuators = static_cast<int64_t>(config.control->actuators.size());
  f.numbers(controller, c, "rest_measures", actuators, "this deck's actuators");
  f.numbers(controller, c, "last_pressures");
  f.count(controller, c, "step_count");
  f.boolean(controller, c, "factored");
  f.count(controller, c, "steps_since_factorization");
  f.number(controller, c, "residual_at_factorization");
  if (controller.contains("step_start_pressures")) f.numbers(controller, c, "step_start_pressures");
  if (controller.contains("factored_constraints"))
    check_constraints(f, controller, c, "factored_constraints", config);
  const std::string l = "position.loop";
  const json& loop = f.at(p, "position", "loop");
  f.objects(loop, l, "targets");
  f.numbers(loop, l, "step_ms");
  const json& parts = f.at(loop, l, "parts_ms");
  if (!parts.is_object()) f.fail(l + ".parts_ms", "must be an object");
  for (const auto& [name, times] : parts.items()) f.numbers(parts, l + ".parts_ms", name);
  f.number(loop, l, "kkt_residual_max");
  f.count(loop, l, "unsolved");
  if (f.count(loop, l, "sets") != done)
    f.fail(l + ".sets", "must equal position.target_set, " + std::to_string(done));
  f.counts(loop, l, "staleness");
  f.counts(loop, l, "correction_iterations");
  f.array(loop, l, "failures");
  f.count(loop, l, "newton_iterations");
}

}  // namespace

void check_checkpoint_state(const nlohmann::json& state, const Config& config,
                            const std::string& file) {
  const Fields f(file);
  const std::string where = "--restart: " + file + ": ";
  if (!state.is_object()) f.fail("state", "must be an object");
  const std::string kind = f.text(state, "", "kind"), mine = stepping_kind(config);
  if (kind != mine)
    throw InputError(where + "written by a " + kind + " run, this deck runs " + mine);
  const std::string fingerprint = f.text(state, "", "fingerprint");
  if (fingerprint != config_fingerprint(config))
    throw InputError(where + "written for another deck or other values (" +
                     (state.contains("deck") && state["deck"].is_string()
                          ? state["deck"].get<std::string>()
                          : std::string("?")) +
                     "; configuration fingerprint " + fingerprint + ", this deck's " +
                     config_fingerprint(config) + "; only output keys may differ)");
  f.integer(state, "", "nodes", 1, int64_t{1} << 40);
  f.integer(state, "", "elements", 1, int64_t{1} << 40);
  f.integer(state, "", "order", 1, 2);
  f.integer(state, "", "ranks", 1, INT_MAX);
  f.text(state, "", "deck");
  f.numbers(state, "", "coordinate_checksum", 2);
  const json& stats = f.at(state, "", "stats");
  for (const char* count : {"steps", "cutbacks", "newton_iterations", "linear_iterations"})
    f.count(stats, "stats", count);
  f.number(stats, "stats", "max_stored_energy");
  if (!state.contains("position")) throw InputError(where + "holds no stepping position");
  const json& p = state.at("position");
  if (!p.is_object()) f.fail("position", "must be an object");
  const bool target_sets = kind == "control" && p.contains("target_set");
  if (kind == "static")
    check_static(f, p, config);
  else if (kind == "dynamic")
    check_dynamic(f, p, config);
  else if (kind == "dynamic_states")
    check_dynamic_states(f, p, config);
  else if (target_sets)
    check_control(f, p, config);
  else
    check_states(f, p, config);
  // A control deck's states end with `last` set; its target sets go on from there.
  if (p.at("last").get<bool>() && (kind != "control" || target_sets))
    throw InputError(where + "written at the run's last step; nothing is left to run");
}

}  // namespace hs
