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

// Where the prescribed boundary moves from load factor s_from to s and no earlier converged
// state gives a secant (the first increment, and its cut-back retries): u (converged at
// s_from) moved by the tangent's prediction, the boundary's jump and the interior's
// first-order response to it and to the loads' increment (Euler's predictor), so that the
// first residual is not taken on elements next to the boundary strained by the whole jump
// (in a nearly incompressible body, nu 0.4999, a pressure of hundreds of mu and a first
// Newton step that inverts an element). False, u unchanged, where the boundary does not move,
// the step cannot be taken or the prediction inverts an element. Collective.
bool predict_by_tangent(Problem& problem, NonlinearSolver& solver, Vec u, double s_from, double s);

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
