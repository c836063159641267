// The secant predictor of the load and state stepping: each increment starts from the
// extrapolation of the last two converged states, so that a prescribed boundary motion moves
// the interior along with it instead of distorting the elements next to the boundary, and a
// cavity's pressure starts near where the ramp takes it.
#pragma once

#include <petscvec.h>

#include <vector>

#include "solvers/petsc_handle.hpp"
#include "solvers/problem.hpp"

namespace hs {

class SecantPredictor {
 public:
  explicit SecantPredictor(const Problem& problem);

  // Keeps the converged state (u at parameter(), with its multipliers, empty without
  // constraints), then moves u and the multipliers along the secant through the previous
  // converged state to t: u <- u + (t - t1) / (t1 - t0) (u - u0), exact for a path linear in
  // t. Without a previous state they stay where they are.
  void predict(Vec u, std::vector<double>& multipliers, double t);
  // The solve from the prediction converged at t: the kept state becomes the previous one.
  void accept(double t);
  // It failed: u and the multipliers go back to the kept state; the history still holds.
  void reject(Vec u, std::vector<double>& multipliers) const;
  // A new path from here (the next state of a deck): parameter 0, no previous state.
  void start_path();

  // What a checkpoint keeps: the parameter of u, the previous state and its parameter and
  // multipliers; resume() puts them back (previous() filled first).
  double parameter() const { return t_; }
  double previous_parameter() const { return t_last_; }
  bool has_previous() const { return has_last_; }
  Vec previous() const { return u_last_; }
  const std::vector<double>& previous_multipliers() const { return lambda_last_; }
  void resume(double t, double t_last, bool has_last, std::vector<double> lambda_last);

 private:
  double t_ = 0;           // parameter of the converged state
  double t_last_ = 0;      // parameter of u_last_
  bool has_last_ = false;  // u_last_ holds an earlier converged state
  std::vector<double> lambda_last_, lambda_saved_;
  VecHandle u_last_, saved_;
};

}  // namespace hs
