// What every stepping shares (solvers/stepping/): the run's counts, the load schedule, and the
// automatic cutback of a step with the bounds that end it.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "deck/config.hpp"
#include "solvers/problem.hpp"
#include "solvers/stepping/nonlinear_solver.hpp"

namespace hs {

struct SteppingStats {
  int steps = 0;  // converged solves (sub-increments included)
  int cutbacks = 0;
  // The most converged solves the run may take (0: no bound): set by the run from its plan,
  // kSubstepsPerPlannedStep per planned step and at least kMinSubstepsPerRun.
  int64_t max_steps = 0;
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

// The bounds that end the cutbacks of one step (docs/reliability.md, "Load stepping always
// ends"). Without them a step whose sub-steps converged ever closer to where it stuck halved
// its increment until the parameter no longer changed, and then solved at that same value
// forever. The halvings in a row are the deck's time.max_cutbacks.
inline constexpr int kCutbacksPerStepPerMaxCutbacks = 8;  // failed solves in one step, in all
inline constexpr double kMinIncrement = 0x1p-40;          // of the step (9.1e-13)
inline constexpr int64_t kSubstepsPerPlannedStep = 16;    // a run's converged solves ...
inline constexpr int64_t kMinSubstepsPerRun = 256;        // ... and at least this many

// The bound on a run's converged solves for a plan of `planned` steps.
int64_t max_substeps(int64_t planned);

// Advances a parameter (a load factor, a fraction of a state) from `from` to `to`: tries the
// whole way, halves the increment after a failed solve and doubles it again after a success,
// until one of the bounds above ends it: give_up(t, result, why) then throws, t the parameter
// of the last solve and why the Newton failure and the bound in words. attempt(t) solves at t
// from the last converged state and, when it fails, puts that state back. Before every solve
// but the first the ranks of comm ask whether a signal came (stop_if_interrupted, which
// throws Interrupted with that state in place): a step that cuts back for long still stops
// within one solve. Counts steps, cutbacks and iterations into stats.
void advance_with_cutback(
    double from, double to, int max_cutbacks, SteppingStats& stats, MPI_Comm comm,
    const std::function<NewtonResult(double)>& attempt,
    const std::function<void(double, const NewtonResult&, const std::string&)>& give_up);

// "Newton did not converge (REASON, residual R after N iterations)".
std::string newton_failure(const NewtonResult& r);

// A time step's time for people (progress lines, errors): 12 significant digits, so that
// step 3 of 0.1 s reads 0.3 s, not n dt's 0.30000000000000004.
std::string format_time(double seconds);

// Throws SolveError "step STEP (WHERE): WHY", naming the inverted element if there is one.
[[noreturn]] void fail_step(const Problem& problem, int step, const std::string& where,
                            const std::string& why);

}  // namespace hs
