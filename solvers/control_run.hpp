// The control loop of a deck with a `control` section (docs/control.md): after the deck's
// states (the rest state), every target set gets control.steps_per_target steps of the
// inverse controller; its result (target, reached position, error, actuation, saturated
// actuators) goes to summary.json's `targets`, the step times to `step_time_ms`. Targets
// come from the deck or, with `--targets -`, from standard input (the interactive mode): one
// line each ("x y z" for the first effector, or "effector x y z"), and every line gets one
// JSON line at once on standard output, its answer or why it was refused; a bad line does
// not end the run, only the end of the input does.
#pragma once

#include <array>
#include <nlohmann/json.hpp>
#include <string>

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
  // From configuration u at the end of the states (the rest state): every target set,
  // recorded as one output step each after first_time. Returns the summary keys
  // `targets`, `step_time_ms`, `qp`, and in the interactive mode `input`.
  nlohmann::json run(Vec u, ResultRecorder& recorder, double first_time);

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

 private:
  void check_reach(const ControlTarget& target) const;

  const Config& config_;
  Problem& problem_;
  ConstraintSet& constraints_;
  int newton_iterations_ = 0;
  Effectors effectors_;
  InverseController controller_;
  InteractiveIo io_;
  std::array<double, 3> body_low_{}, body_high_{};  // the mesh's bounding box (reference)
};

}  // namespace hs
