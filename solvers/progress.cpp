#include "solvers/progress.hpp"

#include <cstdio>
#include <iostream>

namespace hs {

Progress::Progress(bool enabled, MPI_Comm comm, int total_steps)
    : total_(total_steps), start_(MPI_Wtime()), last_step_end_(start_) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  enabled_ = enabled && rank == 0;
}

std::string Progress::line(int k, int total, const std::string& what, int newton_step,
                           int newton_total, int cutbacks_step, int cutbacks_total,
                           double elapsed_s, double left_s) {
  char cutbacks[64] = "";
  if (cutbacks_total > 0)
    std::snprintf(cutbacks, sizeof cutbacks, "  cutbacks %d (%d in all)", cutbacks_step,
                  cutbacks_total);
  char text[384];
  std::snprintf(text, sizeof text,
                "hydrosoft: step %d/%d  %s%s  Newton %d (%d in all)  elapsed %.1f s  left ~%.1f s",
                k, total, what.c_str(), cutbacks, newton_step, newton_total, elapsed_s, left_s);
  return text;
}

double Progress::time_left(const std::deque<double>& recent_durations, int steps_left) {
  if (recent_durations.empty() || steps_left <= 0) return 0;
  double sum = 0;
  for (double d : recent_durations) sum += d;
  return sum / static_cast<double>(recent_durations.size()) * steps_left;
}

void Progress::step(int k, const std::string& what, int newton_total, int cutbacks_total) {
  if (!enabled_) return;
  const double now = MPI_Wtime();
  recent_.push_back(now - last_step_end_);
  if (recent_.size() > kRecentSteps) recent_.pop_front();
  last_step_end_ = now;
  std::cerr << line(k, total_, what, newton_total - newton_before_, newton_total,
                    cutbacks_total - cutbacks_before_, cutbacks_total, now - start_,
                    time_left(recent_, total_ - k))
            << std::endl;
  newton_before_ = newton_total;
  cutbacks_before_ = cutbacks_total;
}

}  // namespace hs
