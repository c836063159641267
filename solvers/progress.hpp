// Progress of a run for the person watching it: one line per converged step on rank 0's
// standard error (what, step k of n, Newton iterations, elapsed and an estimate of the time
// left from the mean step so far), so that a long run never sits silent. `output.progress:
// false` in the deck, or -q on the command line, turns it off.
#pragma once

#include <mpi.h>

#include <string>

namespace hs {

class Progress {
 public:
  Progress(bool enabled, MPI_Comm comm, int total_steps);
  // After step k (1-based) of the total; `what` says where the run is ("load 0.5",
  // "time 0.01 s", "state inflate 0.25"); newton_total: the run's Newton iterations so far.
  void step(int k, const std::string& what, int newton_total);
  // The line it would print (tests).
  static std::string line(int k, int total, const std::string& what, int newton_step,
                          int newton_total, double elapsed_s);

 private:
  bool enabled_ = false;
  int total_ = 0, newton_before_ = 0;
  double start_ = 0;
};

}  // namespace hs
