// Runs the states of a deck (docs/decks.md, "states"): the first ramps the load factor from
// 0 to 1 with the cavities at their own controls; each later state ramps the cavity controls
// it names from their current values to its targets. Every increment is one bordered Newton
// solve (solvers/bordered_newton.hpp) with a secant predictor and automatic cutback, and
// with the paper's linearized coupling the liquid's weight is frozen at its start.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>

#include "solvers/bordered_newton.hpp"
#include "solvers/checkpoint.hpp"
#include "solvers/constraints/constraint_set.hpp"
#include "solvers/output/result_recorder.hpp"
#include "solvers/stepping.hpp"

namespace hs {

struct StateRun {
  nlohmann::json states = nlohmann::json::array();  // one entry per state, for summary.json
};

// u starts at rest (zero), or at `restart`'s position (u, the constraints and the stepper
// read from it). Writes every output.every-th increment and the last of every state; the step
// attribute `time` is state index + fraction of the state (1.0 = end of the first state, 2.0 =
// end of the second, ...). Hands `checkpoints` the position after every increment.
StateRun run_states(const Config& config, Problem& problem, ConstraintSet& constraints,
                    BorderedNewton& newton, ResultRecorder& recorder, Vec u, SteppingStats& stats,
                    MPI_Comm comm, Checkpointer& checkpoints, const Restart* restart = nullptr);

// The orientation of a face group's mean normal (summary.json's per-state `tip`), in degrees:
// inclination_deg, below the plane normal to gravity (positive: tilted towards gravity),
// asin(n . g / |g|): the paper's tip angle when the face is vertical in the undeformed mesh;
// rotation_deg, the angle between the mean normal now and in the undeformed mesh, which
// means the same for a face of any orientation.
struct TipOrientation {
  double inclination_deg = 0;
  double rotation_deg = 0;
};
TipOrientation tip_orientation(Problem& problem, const std::string& group,
                               const std::array<double, 3>& gravity, Vec u);

}  // namespace hs
