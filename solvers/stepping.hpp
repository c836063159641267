// Load stepping with automatic cutback (static, quasi-static) and implicit time stepping
// (Newmark, backward Euler) on top of NewtonSolver.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "deck/config.hpp"
#include "solvers/newton_solver.hpp"
#include "solvers/problem.hpp"

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

// Moves a converged state from one load factor to the next, halving the increment when
// Newton fails and growing it back after a success (advance_with_cutback's bounds).
// Each increment starts from a secant predictor, the extrapolation of the last two converged
// states, so that a prescribed boundary motion moves the interior along with it instead of
// distorting the elements next to the boundary. Throws SolveError naming the step, the load
// factor and the cause when it cannot go on.
class LoadStepper {
 public:
  LoadStepper(Problem& problem, NewtonSolver& newton, int max_cutbacks);
  LoadStepper(const LoadStepper&) = delete;
  LoadStepper& operator=(const LoadStepper&) = delete;

  // u holds the converged state at the current load factor (0 at the start).
  void advance(Vec u, double s_to, int step, SteppingStats& stats);

  // What the secant predictor remembers, for a checkpoint: the load factor of u, the previous
  // converged state and its load factor; resume() puts them back (previous() filled first).
  double load_factor() const { return s_; }
  double previous_load_factor() const { return s_last_; }
  bool has_previous() const { return has_last_; }
  Vec previous() const { return u_last_; }
  void resume(double s, double s_last, bool has_last) {
    s_ = s;
    s_last_ = s_last;
    has_last_ = has_last;
  }

 private:
  void predict(Vec u, double s_next);

  Problem& problem_;
  NewtonSolver& newton_;
  int max_cutbacks_;
  double s_ = 0;           // load factor of u
  double s_last_ = 0;      // load factor of u_last_
  bool has_last_ = false;  // u_last_ holds an earlier converged state
  VecHandle u_last_, saved_;
};

// Called after every converged time step with (step index, time, u, v, a).
using StepCallback = std::function<void(int, double, Vec, Vec, Vec)>;

// Where a restarted dynamic run starts: its step, and fill(v, a) sets the velocity and the
// acceleration there (u is given); stats.energy holds the energies so far.
struct DynamicResume {
  int step = 0;
  std::function<void(Vec v, Vec a)> fill;
};

// Implicit dynamics at full load from rest: u(0) = Dirichlet values, v(0) = 0,
// M a(0) = f_ext - f_int(u(0)); or, with `resume`, from its step on.
void run_dynamic(Problem& problem, NewtonSolver& newton, const TimeConfig& time, Vec u,
                 SteppingStats& stats, const StepCallback& on_step,
                 const DynamicResume* resume = nullptr);

}  // namespace hs
