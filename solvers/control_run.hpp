// The control loop of a deck with a `control` section (docs/control.md): after the deck's
// states (the rest state), every target set gets control.steps_per_target steps of the
// inverse controller; its result (target, reached position, error, actuation, saturated
// actuators) goes to summary.json's `targets`, the step times to `step_time_ms`. Targets
// come from the deck or, with `--targets -`, from standard input (the interactive mode): one
// line each ("x y z" for the first effector, or "effector x y z"), and every line gets one
// JSON line at once on standard output, its answer or why it was refused; a bad line does
// not end the run, only the end of the input does. A batch run checkpoints at target-set
// boundaries and continues from one (docs/control.md, "Checkpoints and restarts").
#pragma once

#include <array>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "solvers/interactive_io.hpp"
#include "solvers/inverse_controller.hpp"
#include "solvers/output/result_recorder.hpp"

namespace hs {

// Built before any work, so that a bad effector (outside the mesh, a point group without
// exactly one node), actuator (a sealed chamber, an unknown cavity) or deck target (too far
// from the body to be answered) stops the run first.
class ControlLoop {
 public:
  ControlLoop(const Config& config, Problem& problem, ConstraintSet& constraints,
              BorderedNewton& newton, InteractiveIo io = {});
  // From configuration u at the end of the states (the rest state), or after resume() from
  // the checkpoint's target set: every (remaining) target set, recorded as one output step
  // each after first_time. After each, `checkpoints` writes a checkpoint when one is due
  // (its count starts at the first target set), holding `states` (summary.json's, so far).
  // Returns the summary keys `targets`, `step_time_ms`, `qp`, and in the interactive mode
  // `input`.
  nlohmann::json run(Vec u, ResultRecorder& recorder, double first_time,
                     Checkpointer* checkpoints = nullptr, const nlohmann::json& states = {});

  // Whether a checkpoint was written by the control loop (else by the states before it).
  static bool resumes(const Restart& restart);
  // Collective: puts back u, the constraints, the controller and the results so far from a
  // checkpoint of the control loop; returns the summary's `states` of the run it came from.
  nlohmann::json resume(const Restart& restart, Vec u);

  // The target set of one interactive line; throws InputError with the reason (the line is
  // named by the caller): the words (parse_target_words), an unknown effector, or a target
  // too far from the body (target_reach_problem).
  std::vector<ControlTarget> targets_of_line(const std::string& line) const;

  // Collective: the history's columns at u (docs/output.md): effector_<name>_x_m, _y_m, _z_m
  // per effector, and per actuator its actuation, actuator_<name>_Pa (a cavity's pressure)
  // or actuator_<name>_N (a cable's tension).
  void add_history(Vec u, HistoryRow& row) const;
  // The control steps' Newton iterations so far.
  int newton_iterations() const { return newton_iterations_; }
  // The summary's `targets` entries of the target sets finished so far: what a failed or
  // stopped run keeps in its .failed summary.json.
  const nlohmann::json& targets_so_far() const { return totals_.targets; }

 private:
  void check_reach(const ControlTarget& target) const;

  // What run() keeps between target sets for summary.json: the entries of `targets` and
  // the steps' times so far (a checkpoint holds it: the statistics cover the whole run).
  struct Totals {
    nlohmann::json targets = nlohmann::json::array();
    std::vector<double> total;  // each step's time and its parts (ms)
    std::map<std::string, std::vector<double>> parts;
    double kkt_max = 0;
    int unsolved = 0, sets = 0;
    // control.factor_threads > 0: per step, the staleness of the preconditioning
    // factorization and the correction's iterations; the background factorizations that
    // failed.
    std::vector<int> staleness, iterations;
    nlohmann::json failures = nlohmann::json::array();
  };
  nlohmann::json totals_state() const;

  const Config& config_;
  Problem& problem_;
  ConstraintSet& constraints_;
  int newton_iterations_ = 0;
  Effectors effectors_;
  InverseController controller_;
  InteractiveIo io_;
  Totals totals_;
  bool resumed_ = false;
  std::array<double, 3> body_low_{}, body_high_{};  // the mesh's bounding box (reference)
};

}  // namespace hs
