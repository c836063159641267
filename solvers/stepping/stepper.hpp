// One interface for every kind of stepping (solvers/stepping/stepping_kind.hpp), so that a
// run (run_simulation) is one loop: advance a planned step, say where it is, write the output
// and the checkpoint when due, stop on a signal. Output, checkpoints and signals are the
// driver's, written once; a stepper only moves u along its plan and says where it got.
//
// Written for what comes next: a stepper solves through a NonlinearSolver (solve(u, s)), not
// through SNES, so a second field (a pressure unknown, a vector of its own in
// checkpoint_fields()), a contact whose active set changes within a step (a solver that
// iterates the set inside solve()) or a reduced model in place of the full solve come as a
// solver or a stepper of their own, and the driver does not change.
#pragma once

#include <petscvec.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "solvers/checkpoint.hpp"
#include "solvers/interactive_io.hpp"
#include "solvers/output/result_recorder.hpp"
#include "solvers/stepping/stepping_kind.hpp"

namespace hs {

// Where a planned step ended: its progress line, its output step and its load factor.
struct StepReport {
  int index = 0;           // planned steps of the phase done so far, restarts' included
  std::string what;        // the progress line's: "load 0.5", "time 0.01 s", "state inflate 0.25"
  double time = 0;         // the output step's time (a load factor, seconds, a state time, ...)
  double load_factor = 1;  // of u
  std::string time_kind;   // what `time` is, for ResultRecorder::record ("": the history's)
  bool output = false;     // the plan writes this step (every output.every-th, the last)
};

class Stepper {
 public:
  virtual ~Stepper() = default;
  // A run may have phases, each with its own plan: a control deck's states, then its target
  // sets (phase 1). Progress lines and checkpoint intervals count within a phase.
  virtual int phase() const { return 0; }
  // The planned steps of the current phase (0: not known ahead, the interactive mode).
  virtual int planned_steps() const = 0;
  virtual bool done() const = 0;
  // Takes the next planned step from u (cutbacks inside), or finds there is none: the end of
  // the interactive input, or the bookkeeping at the end of the last state (nullopt).
  virtual std::optional<StepReport> advance(Vec u) = 0;
  // The step just taken is about to be written as output step `step` (the states and the
  // control loop name it). Called before the write, so that an interactive answer, which
  // carries the number, goes out without waiting for the file.
  virtual void number_output(int step) { (void)step; }
  // The output step of the start, before any step (a dynamic run's t = 0), if any.
  virtual std::optional<StepReport> initial_output() const { return std::nullopt; }

  // Checkpoints: the position after the last step (JSON scalars and objects), the vectors and
  // series it needs besides; resume() puts u and the stepper back there (collective).
  virtual nlohmann::json position() const = 0;
  virtual NamedVecs checkpoint_fields(Vec u) const = 0;
  virtual NamedValues checkpoint_series() const { return {}; }
  virtual void resume(const Restart& restart, Vec u) = 0;

  // The run's Newton iterations for the progress line (the control steps count their own).
  virtual int newton_iterations() const = 0;
  // Static load stepping is verified against the deck's exact solution after every step.
  virtual bool verifies() const { return false; }
  // The load factor the final state is compared with the exact solution at.
  virtual double final_load_factor() const { return 1.0; }
  // Its columns of the history (the control loop's effectors and actuators).
  virtual void add_history(HistorySources& sources) const { (void)sources; }
  // summary.json's keys of this kind of stepping (the states, the targets, ...). The second
  // form: what a run that failed or stopped keeps.
  virtual void add_summary(nlohmann::json& summary) const { (void)summary; }
  virtual void add_failed_summary(nlohmann::json& summary) const { (void)summary; }
};

class NonlinearSolver;
class BorderedNewton;
class ConstraintSet;

// What the steppers are made of; the pointers for constraints are null without them.
struct StepperParts {
  const Config& config;
  Problem& problem;
  NonlinearSolver& solver;
  SteppingStats& stats;
  ConstraintSet* constraints = nullptr;
  BorderedNewton* bordered = nullptr;
  const ResultRecorder* recorder = nullptr;
};

// The stepper of the deck's kind (stepping_kind_of). A control deck's ControlLoop checks its
// effectors, actuators and targets here, before any work.
std::unique_ptr<Stepper> make_stepper(const StepperParts& parts, InteractiveIo io);

}  // namespace hs
