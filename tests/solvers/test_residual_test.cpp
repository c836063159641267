// The bordered Newton's convergence test on residual histories: a residual stalled within one
// column's weight (a column method's resolution) converges, as one at its round-off does; a
// falling one, or one stalled above every floor, goes on.
#include <gtest/gtest.h>

#include "solvers/residual_test.hpp"

namespace test_residual_test {

// A hydraulic robot's step: the residual stuck at 2.09e-6 N against a tolerance of 7.2e-11 N
// and a first residual of 50 N (rtol 1e-8: 5e-7 N); one column of its grid weighs 5.9e-6 N.
TEST(ResidualTest, StalledWithinOneColumnsWeightConverges) {
  int roundoff_calls = 0;
  hs::ResidualTest test{7.2e-11, 1e-8, [&] { return ++roundoff_calls, 1e-12; }, 5.9e-6};
  double floor = 0;
  EXPECT_EQ(hs::residual_verdict(test, 3, 2.09e-6, 50, 2.3e-6, true, floor),
            "converged (|R| within one column's weight, the column method's resolution)");
  EXPECT_EQ(floor, 5.9e-6);
  EXPECT_EQ(roundoff_calls, 0);  // the jump alone decides: no assembly asked for
  // The same history with a smooth load (the closed form) is not converged: it stalls above
  // its round-off, and the stepping cuts the step back.
  test.jump = 0;
  EXPECT_EQ(hs::residual_verdict(test, 3, 2.09e-6, 50, 2.3e-6, true, floor), "");
  EXPECT_EQ(roundoff_calls, 1);
  EXPECT_EQ(floor, 1e-12);
}

TEST(ResidualTest, AFallingResidualIsLeftToFall) {
  hs::ResidualTest test{7.2e-11, 1e-8, [] { return 1e-12; }, 5.9e-6};
  double floor = 0;
  EXPECT_EQ(hs::residual_verdict(test, 3, 2.09e-6, 50, 4.2e-6, true, floor), "");  // halved
  EXPECT_EQ(hs::residual_verdict(test, 1, 2.09e-6, 50, 2.1e-6, true, floor), "");  // too early
}

TEST(ResidualTest, ToleranceRelativeToleranceRoundoffAndControls) {
  hs::ResidualTest test{1e-9, 1e-8, [] { return 3e-9; }, 0};
  double floor = 0;
  EXPECT_EQ(hs::residual_verdict(test, 0, 9e-10, 50, 9e-10, true, floor), "converged");
  EXPECT_EQ(hs::residual_verdict(test, 0, 4e-7, 50, 4e-7, true, floor), "");  // r0 itself
  EXPECT_EQ(hs::residual_verdict(test, 2, 4e-7, 50, 5e-6, true, floor), "converged");
  EXPECT_EQ(hs::residual_verdict(test, 4, 2.5e-9, 0.01, 2.6e-9, true, floor),
            "converged (|R| at its round-off)");
  EXPECT_EQ(floor, 3e-9);
  EXPECT_EQ(hs::residual_verdict(test, 4, 3.5e-9, 0.01, 3.6e-9, true, floor), "");
  // Whatever the residual, a control not met (a pressure or volume off its target) goes on.
  EXPECT_EQ(hs::residual_verdict(test, 4, 1e-20, 50, 1e-20, false, floor), "");
}

}  // namespace test_residual_test
