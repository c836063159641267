// Progress of a run for the person watching it: one line per converged step on rank 0's
// standard error (what, step k of n, the cutbacks once there were any, Newton iterations,
// elapsed and an estimate of the time left from the mean step so far), so that a long run
// never sits silent. The cutbacks are shown as they happen: without them "step 14/14" was
// followed by "done: 18 steps", the 4 sub-steps they added unexplained. `output.progress:
// false` in the deck, or -q on the command line, turns it off.
#pragma once

#include <mpi.h>

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
                          int newton_total, int cutbacks_step, int cutbacks_total,
                          double elapsed_s);

 private:
  bool enabled_ = false;
  int total_ = 0, newton_before_ = 0, cutbacks_before_ = 0;
  double start_ = 0;
};

}  // namespace hs
