// The control loop of a deck with a `control` section (docs/control.md): after the deck's
// states (the rest state), every target set gets control.steps_per_target steps of the
// inverse controller; its result (target, reached position, error, actuation, saturated
// actuators) goes to summary.json's `targets`, the step times to `step_time_ms`. Targets
// come from the deck or, with `--targets -`, from standard input, one line each
// ("x y z" for the first effector, or "effector x y z"), each answered at once on standard
// output with one JSON line.
#pragma once

#include <nlohmann/json.hpp>

#include "solvers/inverse_controller.hpp"
#include "solvers/output/result_recorder.hpp"

namespace hs {

// Parses one line of `--targets -` input; throws InputError naming the line on bad input.
std::vector<ControlTarget> parse_target_line(const std::string& line, const Effectors& effectors,
                                             int line_number);

// Built before any work, so that a bad effector (outside the mesh, a point group without
// exactly one node) or actuator (a sealed chamber, an unknown cavity) stops the run first.
class ControlLoop {
 public:
  ControlLoop(const Config& config, Problem& problem, ConstraintSet& constraints,
              BorderedNewton& newton);
  // From configuration u at the end of the states (the rest state): every target set,
  // recorded as one output step each after first_time. Returns the summary keys
  // `targets`, `step_time_ms`, `qp`.
  nlohmann::json run(Vec u, ResultRecorder& recorder, double first_time);

 private:
  const Config& config_;
  Problem& problem_;
  Effectors effectors_;
  InverseController controller_;
};

}  // namespace hs
