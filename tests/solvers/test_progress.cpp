// The progress line's estimate of the time left: from the last steps' durations, so that it
// follows a run whose steps speed up (the mean since the start announced 989 s for a run of
// 353 s whose first steps were the slowest).
#include <gtest/gtest.h>

#include "solvers/progress.hpp"

namespace {

TEST(Progress, TimeLeftFollowsTheLastSteps) {
  // A slow first step (30 s), then steps of 2 s: after step 4 of 10 the recent steps say 12 s;
  // the mean since the start would have said 54 s.
  std::deque<double> recent;
  for (double d : {30.0, 2.0, 2.0, 2.0}) {
    recent.push_back(d);
    if (recent.size() > hs::Progress::kRecentSteps) recent.pop_front();
  }
  EXPECT_DOUBLE_EQ(hs::Progress::time_left(recent, 6), 12.0);
  EXPECT_DOUBLE_EQ(hs::Progress::time_left({}, 6), 0.0);
  EXPECT_DOUBLE_EQ(hs::Progress::time_left(recent, 0), 0.0);
  // Steps that slow down: the estimate grows with them.
  EXPECT_DOUBLE_EQ(hs::Progress::time_left({1.0, 2.0, 6.0}, 2), 6.0);
}

TEST(Progress, LineShowsTheEstimateItIsGiven) {
  const std::string line = hs::Progress::line(4, 10, "load 0.4", 3, 20, 0, 0, 40.0, 12.0);
  EXPECT_NE(line.find("step 4/10  load 0.4  Newton 3 (20 in all)  elapsed 40.0 s  left ~12.0 s"),
            std::string::npos)
      << line;
}

}  // namespace
