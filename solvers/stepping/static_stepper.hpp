// Static and quasi-static load stepping: the load factors of time.schedule (or a ramp of
// time.steps equal increments to 1), one planned step each, every increment from the secant
// predictor with automatic cutback (advance_with_cutback). Throws SolveError naming the step,
// the load factor and the cause when it cannot go on.
#pragma once

#include <vector>

#include "solvers/stepping.hpp"
#include "solvers/stepping/secant_predictor.hpp"
#include "solvers/stepping/stepper.hpp"

namespace hs {

class StaticStepper : public Stepper {
 public:
  StaticStepper(const Config& config, Problem& problem, NonlinearSolver& solver,
                SteppingStats& stats);

  int planned_steps() const override { return static_cast<int>(schedule_.size()); }
  bool done() const override { return next_ == schedule_.size(); }
  std::optional<StepReport> advance(Vec u) override;

  nlohmann::json position() const override;
  NamedVecs checkpoint_fields(Vec u) const override;
  void resume(const Restart& restart, Vec u) override;

  int newton_iterations() const override { return stats_.newton_iterations; }
  bool verifies() const override { return true; }
  double final_load_factor() const override { return schedule_.back(); }

 private:
  const Config& config_;
  Problem& problem_;
  NonlinearSolver& solver_;
  SteppingStats& stats_;
  std::vector<double> schedule_;
  size_t next_ = 0;  // the index of the next load factor: the steps done
  SecantPredictor predictor_;
};

}  // namespace hs
