// Runs the states of a deck (state_plan.hpp): every increment is one solve of the bordered
// Newton (solvers/bordered_newton.hpp) from the secant predictor (displacements and
// multipliers) with automatic cutback, and with the paper's linearized coupling the liquid's
// weight is frozen at its start. The output step's time is state index + fraction of the state
// (1.0 = end of the first state, 2.0 = end of the second, ...); every output.every-th increment
// and the last of every state are written. At the end of each state its entry of summary.json's
// `states` is made (load factor, tip, volumes, cavities and cables).
#pragma once

#include <vector>

#include "solvers/constraints/constraint_set.hpp"
#include "solvers/stepping.hpp"
#include "solvers/stepping/secant_predictor.hpp"
#include "solvers/stepping/state_plan.hpp"
#include "solvers/stepping/stepper.hpp"

namespace hs {

class StatesStepper : public Stepper {
 public:
  StatesStepper(const Config& config, Problem& problem, ConstraintSet& constraints,
                NonlinearSolver& solver, SteppingStats& stats, const ResultRecorder& recorder);

  int planned_steps() const override { return total_; }
  bool done() const override { return k_ == plans_.size(); }
  std::optional<StepReport> advance(Vec u) override;

  nlohmann::json position() const override;
  NamedVecs checkpoint_fields(Vec u) const override;
  void resume(const Restart& restart, Vec u) override;
  // Every state done before a checkpoint of a later phase (the control loop's), with summary.json's
  // `states` as it holds them.
  void resume_done(nlohmann::json states);

  int newton_iterations() const override { return stats_.newton_iterations; }
  // summary.json's `states`, and `end_of_run`: the constraints after the last state (in a
  // control run, after its last target set).
  void add_summary(nlohmann::json& summary) const override;
  // summary.json's `states` so far.
  const nlohmann::json& states() const { return states_; }

 private:
  // Takes the current state from the last converged point to tau.
  void solve_increment(Vec u, double tau);
  // The state's entry of summary.json's `states` (and, after the first, the rest volumes).
  void end_state(Vec u);

  const Config& config_;
  Problem& problem_;
  ConstraintSet& constraints_;
  NonlinearSolver& solver_;
  SteppingStats& stats_;
  const ResultRecorder& recorder_;
  std::vector<StatePlan> plans_;
  int total_ = 0, done_ = 0;  // increments planned, and done (restarts' included)
  size_t k_ = 0, i_ = 0;      // the current state, and its increments done
  bool begun_ = false;        // the current state's ramps are fixed
  SecantPredictor predictor_;
  nlohmann::json states_ = nlohmann::json::array();
  // The first state's change of every measure by an exact load (load_model_error.hpp).
  std::vector<double> rest_change_;
};

// A state's entry of summary.json's `states` at its end, on u (collective): its name, time
// (a state time or seconds), output step and load factor, the tip, reactions and contact where
// the deck has them, the added volume and the cavities and cables.
nlohmann::json state_entry(const Config& config, Problem& problem, ConstraintSet& constraints,
                           Vec u, const std::string& name, double time, nlohmann::json step,
                           double load_factor);

}  // namespace hs
