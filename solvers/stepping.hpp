// Load stepping with automatic cutback (static, quasi-static) and implicit time stepping
// (Newmark, backward Euler) on top of NewtonSolver.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "deck/config.hpp"
#include "solvers/newton_solver.hpp"
#include "solvers/problem.hpp"

namespace hs {

struct SteppingStats {
  int steps = 0;              // converged solves (sub-increments included)
  int cutbacks = 0;
  int newton_iterations = 0;
  int linear_iterations = 0;
  // Dynamic runs: total energy (kinetic + stored - work of the external load) after each step,
  // and the initial one. Newmark's trapezoidal rule conserves it for linear elasticity under
  // dead loads; backward Euler dissipates it.
  std::vector<double> energy;
  double max_stored_energy = 0;  // the scale the drift is measured against
};

// The load factors a static or quasi-static run visits: time.schedule, or a ramp of
// time.steps equal increments to 1.
std::vector<double> load_schedule(const TimeConfig& time);

// Moves the converged state u from load factor s_from to s_to, halving the increment when
// Newton fails (at most max_cutbacks times in a row). Throws SolveError naming the step, the
// load factor and the cause when it cannot.
void advance_load(Problem& problem, NewtonSolver& newton, Vec u, double s_from, double s_to,
                  int step, int max_cutbacks, SteppingStats& stats);

// Called after every converged time or load step with (step index, time or load factor, u).
using StepCallback = std::function<void(int, double, Vec)>;

// Implicit dynamics at full load from rest: u(0) = Dirichlet values, v(0) = 0,
// M a(0) = f_ext - f_int(u(0)).
void run_dynamic(Problem& problem, NewtonSolver& newton, const TimeConfig& time, Vec u,
                 SteppingStats& stats, const StepCallback& on_step);

}  // namespace hs
