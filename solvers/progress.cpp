#include "solvers/progress.hpp"

#include <cstdio>
#include <iostream>

namespace hs {

Progress::Progress(bool enabled, MPI_Comm comm, int total_steps)
    : total_(total_steps), start_(MPI_Wtime()) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  enabled_ = enabled && rank == 0;
}

std::string Progress::line(int k, int total, const std::string& what, int newton_step,
                           int newton_total, int cutbacks_step, int cutbacks_total,
                           double elapsed_s) {
  char cutbacks[64] = "";
  if (cutbacks_total > 0)
    std::snprintf(cutbacks, sizeof cutbacks, "  cutbacks %d (%d in all)", cutbacks_step,
                  cutbacks_total);
  char text[384];
  const double left = k > 0 && total > k ? elapsed_s / k * (total - k) : 0;
  std::snprintf(text, sizeof text,
                "hydrosoft: step %d/%d  %s%s  Newton %d (%d in all)  elapsed %.1f s  left ~%.1f s",
                k, total, what.c_str(), cutbacks, newton_step, newton_total, elapsed_s, left);
  return text;
}

void Progress::step(int k, const std::string& what, int newton_total, int cutbacks_total) {
  if (!enabled_) return;
  std::cerr << line(k, total_, what, newton_total - newton_before_, newton_total,
                    cutbacks_total - cutbacks_before_, cutbacks_total, MPI_Wtime() - start_)
            << std::endl;
  newton_before_ = newton_total;
  cutbacks_before_ = cutbacks_total;
}

}  // namespace hs
