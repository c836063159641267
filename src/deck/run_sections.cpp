// The sections `time`, `solver` and `output`: their key tables and parsers (docs/decks.md).
#include "deck/run_sections.hpp"

#include <cmath>
#include <regex>

#include "deck/section_keys.hpp"

namespace hs {
namespace {

// A dynamic run of more steps than this is a mistyped dt (and would overflow a step count).
constexpr double kMaxTimeSteps = 1e7;

bool is_dynamic(const TimeConfig& t, const Config&) { return t.type == TimeType::dynamic; }
bool is_not_dynamic(const TimeConfig& t, const Config&) { return t.type != TimeType::dynamic; }

// Functions, not globals: the tables are made on first use, whatever the order of static
// initialization.
KeyUse<TimeConfig> dynamic_only() {
  return use_when<TimeConfig>(is_dynamic, "only used when time.type is dynamic", "dynamic");
}
KeyUse<TimeConfig> not_dynamic() {
  return use_when<TimeConfig>(is_not_dynamic,
                              "not used when time.type is dynamic (dt and end_time set the steps)",
                              "static/quasi-static");
}

}  // namespace

const KeyTable<TimeConfig>& newmark_keys() {
  static const KeyTable<TimeConfig> keys = {
      number_key("beta", &TimeConfig::newmark_beta, above(0), "Newmark's beta"),
      number_key("gamma", &TimeConfig::newmark_gamma, at_least(0.5), "Newmark's gamma"),
  };
  return keys;
}

const KeyTable<TimeConfig>& time_keys() {
  static const TimeConfig defaults;
  static const KeyTable<TimeConfig> keys = {
      enum_key("type", &TimeConfig::type, kTimeTypeNames,
               "`static`, `quasi_static` or `dynamic` (read into an enum: the solver layer never "
               "compares the text)"),
      integer_key("steps", &TimeConfig::steps, at_least(1),
                  "number of load increments of the linear ramp to load factor 1 (not with "
                  "`states`: the first state's `steps`)")
          .only(not_dynamic())
          .only(use_when<TimeConfig>(
              [](const TimeConfig&, const Config& c) { return c.states.empty(); },
              "not used when states are given (the first state's steps replace it)", "")),
      custom_key<TimeConfig>(
          "schedule", "list of numbers", "ramp",
          "the load factor after each step (any finite values, e.g. `[0.5, 1, 0.5]` to unload); "
          "`steps` becomes its length (if both are given they must agree); not with `states`",
          [](const DeckReader& r, const YAML::Node& n, const std::string& key, TimeConfig& t,
             const Config&) {
            t.schedule = r.numbers(n, key);
            require(!t.schedule.empty(), r, n, key, "must hold at least one load factor");
          },
          [](YAML::Emitter& out, const TimeConfig& t, const Config&) {
            write_numbers(out, t.schedule.data(), t.schedule.size());
          })
          .only(not_dynamic())
          .only(use_when<TimeConfig>(
              [](const TimeConfig&, const Config& c) { return c.states.empty(); },
              "not used when states are given (the first state ramps the load linearly over its "
              "steps)",
              ""))
          .printed_when([](const TimeConfig& t) { return !t.schedule.empty(); }),
      integer_key(
          "max_cutbacks", &TimeConfig::max_cutbacks, at_least(0),
          "halvings of a failed load increment in a row before the run gives up; a step gives up "
          "after 8 × `max_cutbacks` failed solves in all, or when its increment would fall below "
          "2^-40 of the step or stop changing the load factor, and a run after 16 converged "
          "solves per planned step (at least 256) (docs/reliability.md, \"Load stepping always "
          "ends\"). A dynamic run takes a time step whose solve fails again in 2, 4, ... equal "
          "sub-steps, at most 2^`max_cutbacks`"),
      number_key("dt", &TimeConfig::dt, above(0),
                 "time step (s), at most `end_time` and at least `end_time` / 1e7")
          .only(dynamic_only())
          .needed(),
      number_key("end_time", &TimeConfig::end_time, above(0),
                 "final time (s); the run takes ⌈end_time / dt⌉ steps")
          .only(dynamic_only())
          .needed(),
      enum_key("integrator", &TimeConfig::integrator, kIntegratorNames,
               "`newmark` or `backward_euler`")
          .only(dynamic_only()),
      custom_key<TimeConfig>(
          "newmark", "`{beta, gamma}`",
          "`{beta: " + doc_number(defaults.newmark_beta) +
              ", gamma: " + doc_number(defaults.newmark_gamma) + "}`",
          "Newmark parameters: β > 0, γ ≥ 1/2 (the average acceleration rule by default; γ > 1/2 "
          "adds numerical damping)",
          [](const DeckReader& r, const YAML::Node& n, const std::string& key, TimeConfig& t,
             const Config& c) { read_keys(r, n, key, newmark_keys(), t, c); },
          [](YAML::Emitter& out, const TimeConfig& t, const Config& c) {
            out << YAML::Flow << YAML::BeginMap;
            write_keys(out, newmark_keys(), t, c);
            out << YAML::EndMap;
          })
          .only(dynamic_only())
          .only(use_when<TimeConfig>(
              [](const TimeConfig& t, const Config&) {
                return t.integrator == Integrator::newmark;
              },
              "only used by integrator newmark", "integrator `newmark`")),
  };
  return keys;
}

const KeyTable<SolverConfig>& solver_keys() {
  static const KeyTable<SolverConfig> keys = {
      enum_key(
          "preset", &SolverConfig::preset, kSolverPresetNames,
          "a starting set of PETSc options: `mumps` (direct MUMPS: L D L^T when the tangent is "
          "symmetric, i.e. no `loads.pressure` on an open surface, LU otherwise; a "
          "nodal-pressure body's tangent through its mixed system, `pc_type: hs_mixed`, "
          "docs/formulation.md) or `gamg` "
          "(algebraic multigrid inside CG when the tangent is symmetric and positive definite, "
          "i.e. linear laws without pressure stiffness, MINRES when it is symmetric but may be "
          "indefinite, GMRES otherwise). Newton takes full steps (`snes_linesearch_type: "
          "basic`); a step that fails is cut back by the load stepping (docs/benchmarks.md, "
          "Newton)"),
      custom_key<SolverConfig>(
          "petsc_options", "map option: value", "none",
          "any PETSc option, written without the leading dash (`ksp_type: cg`), for every "
          "solver object, or with an object's prefix for that one alone (`hs_control_ksp_type: "
          "gmres`; \"Solver options\" below); values are any scalar, kept as text; an empty "
          "value is a flag (`snes_monitor:`). Before any work (and by `--check`), from the "
          "deck or the command line: an option that begins with `hs_` must begin with a solver "
          "object's prefix (an error names the nearest), and PETSc is asked whether every "
          "`*_type` option (KSP, PC, SNES, line search, mesh partitioner, with or without a "
          "prefix) names a type it has",
          [](const DeckReader& r, const YAML::Node& options, const std::string& key,
             SolverConfig& s, const Config&) {
            if (!options.IsMap()) r.fail(key, options, "expected a map of option: value");
            static const std::regex option_name("[A-Za-z][A-Za-z0-9_]*");
            for (const auto& entry : options) {
              const std::string name = entry.first.Scalar();
              const std::string okey = child_key(key, name);
              if (!name.empty() && name[0] == '-')
                r.fail(okey, entry.first, "write PETSc options without the leading dash");
              if (!std::regex_match(name, option_name))
                r.fail(okey, entry.first, "not a PETSc option name (letters, digits and _ only)");
              if (s.petsc_options.count(name)) r.fail(okey, entry.first, "duplicate key");
              if (!entry.second.IsNull() && !entry.second.IsScalar())
                r.fail(okey, entry.second, "expected a single value (or nothing, for a flag)");
              s.petsc_options[name] = entry.second.IsNull() ? "" : entry.second.Scalar();
            }
          },
          [](YAML::Emitter& out, const SolverConfig& s, const Config&) {
            if (s.petsc_options.empty()) out << YAML::Flow;
            out << YAML::BeginMap;
            for (const auto& [name, value] : s.petsc_options)
              out << YAML::Key << name << YAML::Value << value;
            out << YAML::EndMap;
          }),
  };
  return keys;
}

const KeyTable<CheckpointConfig>& checkpoint_keys() {
  static const KeyTable<CheckpointConfig> keys = {
      integer_key("every", &CheckpointConfig::every, at_least(1, "converged steps"),
                  "converged steps between checkpoints")
          .printed_when([](const CheckpointConfig& p) { return p.every > 0; }),
      number_key("minutes", &CheckpointConfig::minutes, above(0),
                 "minutes of wall time between checkpoints")
          .printed_when([](const CheckpointConfig& p) { return p.minutes > 0; }),
  };
  return keys;
}

const KeyTable<OutputConfig>& output_keys() {
  static const KeyTable<OutputConfig> keys = {
      text_key("folder", &OutputConfig::folder, "path",
               "where results go, relative to the working directory (docs/output.md). An "
               "existing folder is replaced, so it must be empty or an earlier hydrosoft output "
               "folder (as must `<folder>.partial`, `.old` and `.failed`). A run that fails or "
               "is stopped by SIGTERM/SIGINT after some steps leaves them in `<folder>.failed` "
               "and the earlier `<folder>` as it was.")
          .defaults_to("`out/<deck name>`"),
      integer_key("every", &OutputConfig::every, at_least(1),
                  "write every n-th step (the last one always, and the step at which a signal "
                  "stops the run); in a control run every n-th target set or `--targets -` "
                  "line, the answers of the others with `step: null` (a client that needs no "
                  "field of every line answers sooner: docs/control.md)"),
      bool_key("progress", &OutputConfig::progress,
               "a line per converged step on standard error: step k/n, load, time or state, "
               "Newton iterations, the cutbacks once there were any, elapsed and estimated time "
               "left (`-q` on the command line sets it false)"),
      custom_key<OutputConfig>(
          "checkpoint", "map `{every: N, minutes: M}`", "none (no checkpoints)",
          "write `checkpoint.h5` into the staging folder after every `N` converged steps "
          "(integer ≥ 1) or `M` minutes of wall time (number > 0) since the last checkpoint, "
          "whichever comes first, and at the step where a signal stops the run; give one or "
          "both. The file holds the latest checkpoint only; `hydrosoft DECK --restart FOLDER` "
          "continues from it (docs/output.md, \"Checkpoints and restarts\"). Static, "
          "quasi-static, dynamic, state (cavity, cable; static or dynamic) and control decks (a "
          "control run counts "
          "target sets as steps); refused with `--targets -` and, in a control deck with "
          "`free_solve: one_step`, with a hydraulic cavity's `coupling: linearized` "
          "(docs/control.md, \"Checkpoints and restarts\")",
          [](const DeckReader& r, const YAML::Node& n, const std::string& key, OutputConfig& o,
             const Config& c) {
            CheckpointConfig checkpoint;
            read_keys(r, n, key, checkpoint_keys(), checkpoint, c);
            if (checkpoint.every == 0 && checkpoint.minutes == 0)
              r.fail(key, n, "needs every (steps) or minutes, or both");
            o.checkpoint = checkpoint;
          },
          [](YAML::Emitter& out, const OutputConfig& o, const Config& c) {
            out << YAML::Flow << YAML::BeginMap;
            write_keys(out, checkpoint_keys(), *o.checkpoint, c);
            out << YAML::EndMap;
          })
          .printed_when([](const OutputConfig& o) { return o.checkpoint.has_value(); }),
  };
  return keys;
}

TimeConfig parse_time(const DeckReader& r, const YAML::Node& node, const Config& c) {
  TimeConfig t;
  read_keys(r, node, "time", time_keys(), t, c);
  if (t.type == TimeType::dynamic) {
    const YAML::Node dt = node["dt"];
    require(t.dt <= t.end_time, r, dt, "time.dt", "must not exceed time.end_time");
    require(t.end_time / t.dt <= kMaxTimeSteps, r, dt, "time.dt",
            "gives " + format_number(std::ceil(t.end_time / t.dt)) + " steps of time.end_time " +
                format_number(t.end_time) + ", more than " + format_number(kMaxTimeSteps));
  }
  if (!t.schedule.empty()) {
    if (node["steps"] && t.steps != static_cast<int>(t.schedule.size()))
      r.fail("time.steps", node["steps"],
             "is " + std::to_string(t.steps) + " but time.schedule has " +
                 std::to_string(t.schedule.size()) + " entries");
    t.steps = static_cast<int>(t.schedule.size());
  }
  return t;
}

SolverConfig parse_solver(const DeckReader& r, const YAML::Node& node, const Config& c) {
  SolverConfig s;
  read_keys(r, node, "solver", solver_keys(), s, c);
  return s;
}

OutputConfig parse_output(const DeckReader& r, const YAML::Node& node, const Config& c) {
  OutputConfig o;
  read_keys(r, node, "output", output_keys(), o, c);
  return o;
}

}  // namespace hs
