// Progress of a run for the person watching it: one line per converged step on rank 0's
// standard error (what, step k of n, the cutbacks once there were any, Newton iterations,
// elapsed and an estimate of the time left from the last steps' durations), so that a long run
// never sits silent. The cutbacks are shown as they happen: without them "step 14/14" was
// followed by "done: 18 steps", the 4 sub-steps they added unexplained. `output.progress:
// false` in the deck, or -q on the command line, turns it off.
#pragma once

#include <mpi.h>

#include <deque>
#include <string>

namespace hs {

class Progress {
 public:
  Progress(bool enabled, MPI_Comm comm, int total_steps);
  // After step k (1-based) of the total; `what` says where the run is ("load 0.5",
  // "time 0.01 s", "state inflate 0.25"); newton_total, cutbacks_total: the run's Newton
  // iterations and cutbacks (halvings of a step's increment) so far.
  void step(int k, const std::string& what, int newton_total, int cutbacks_total);
  // The line it would print (tests).
  static std::string line(int k, int total, const std::string& what, int newton_step,
                          int newton_total, int cutbacks_step, int cutbacks_total, double elapsed_s,
                          double left_s);
  // The time left: the steps to go at the mean duration of the last (up to kRecentSteps)
  // steps. The mean over all steps since the start carried the set-up and the first, slowest
  // steps into every estimate (989 s announced for a run of 353 s); the recent steps follow a
  // run whose steps speed up or slow down. 0 without a step yet.
  static constexpr size_t kRecentSteps = 3;
  static double time_left(const std::deque<double>& recent_durations, int steps_left);

 private:
  bool enabled_ = false;
  int total_ = 0, newton_before_ = 0, cutbacks_before_ = 0;
  double start_ = 0, last_step_end_ = 0;
  std::deque<double> recent_;  // the last steps' durations (s)
};

}  // namespace hs
