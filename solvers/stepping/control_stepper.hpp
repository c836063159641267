// A control deck's stepping: its states (the rest state, StatesStepper), then its target sets
// (ControlLoop, solvers/control_run.hpp), each one planned step of phase 1, every
// output.every-th (and the last) written as one output step. A checkpoint of either phase
// continues there.
#pragma once

#include "solvers/control_run.hpp"
#include "solvers/stepping/states_stepper.hpp"

namespace hs {

class ControlStepper : public Stepper {
 public:
  ControlStepper(const Config& config, Problem& problem, ConstraintSet& constraints,
                 BorderedNewton& newton, SteppingStats& stats, const ResultRecorder& recorder,
                 InteractiveIo io);

  int phase() const override { return states_.done() ? 1 : 0; }
  int planned_steps() const override;
  bool done() const override { return states_.done() && loop_.done(); }
  std::optional<StepReport> advance(Vec u) override;
  void number_output(int step) override;

  nlohmann::json position() const override;
  NamedVecs checkpoint_fields(Vec u) const override;
  void resume(const Restart& restart, Vec u) override;

  int newton_iterations() const override;
  void add_history(HistorySources& sources) const override;
  void add_summary(nlohmann::json& summary) const override;
  void add_failed_summary(nlohmann::json& summary) const override;

 private:
  const SteppingStats& stats_;
  int every_;  // output.every: target sets between output steps
  StatesStepper states_;
  ControlLoop loop_;
  bool started_ = false;  // the loop's rest state is set
};

}  // namespace hs
