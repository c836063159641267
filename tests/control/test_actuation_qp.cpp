// The controller's actuation QP (src/control/actuation_qp.hpp): an actuator whose own bound
// stops it ends exactly on that bound, not within the QP's tolerance of it.
#include <gtest/gtest.h>

#include <random>

#include "control/actuation_qp.hpp"

namespace {

TEST(ActuationQp, AnActuatorStoppedByItsBoundIsExactlyOnIt) {
  // Three coupled cavities at pressures of many digits, moving three effector coordinates;
  // the targets ask for changes beyond the range [0, 8,000] for the first two, within it for
  // the third. Met to the QP's tolerance, a bound is missed by round-off; every actuator a
  // bound stops must sit on it.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(0, 1);
  int exact = 0, bounded = 0;
  for (int k = 0; k < 20; ++k) {
    Eigen::MatrixXd W(3, 3);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) W(i, j) = (i == j ? 1e-6 : 2e-7) * (0.5 + uniform(rng));
    const Eigen::Vector3d at_now(2000 * (0.5 + uniform(rng)), 3000 * (0.5 + uniform(rng)),
                                 4000 * (0.5 + uniform(rng)));
    const Eigen::Vector3d wanted(-at_now(0) - 1000 - 2000 * uniform(rng),
                                 8000 - at_now(1) + 1000 + 2000 * uniform(rng), 100 * uniform(rng));
    const Eigen::VectorXd delta = -W * wanted;
    std::vector<hs::ActuatorConfig> bounds(3);
    for (auto& b : bounds) {
      b.min_multiplier = 0;
      b.max_multiplier = 8000;
    }
    std::vector<hs::ActuatorPosition> at(3);
    for (int a = 0; a < 3; ++a) at[a] = {at_now(a), at_now(a), 0};
    const hs::ActuationChange c =
        hs::solve_actuation_qp(W, delta, Eigen::MatrixXd::Zero(3, 3), bounds, at, 1e-12);
    ASSERT_TRUE(c.solved) << c.status;
    for (int i = 0; i < 3; ++i) {
      if (!c.saturated[i]) continue;
      ++bounded;
      const double p = at_now(i) + c.dl(i);
      exact += p == 0.0 || p == 8000.0;
    }
  }
  EXPECT_GE(bounded, 20);
  EXPECT_EQ(exact, bounded);
}

TEST(ActuationQp, AnActuatorPastItsBoundByRoundOffIsPutBackOnIt) {
  // The targets ask for 2e-12 Pa below the bound of 0 (a few units in the last place of
  // 2,000 Pa): within the QP's tolerance, so no row is active, and the pressure must still
  // not end below 0.
  Eigen::MatrixXd W(1, 1);
  W << 1e-6;
  const double now = 2000, wanted = -now - 2e-12;
  const Eigen::VectorXd delta = -W * Eigen::VectorXd::Constant(1, wanted);
  std::vector<hs::ActuatorConfig> bounds(1);
  bounds[0].min_multiplier = 0;
  const hs::ActuationChange c =
      hs::solve_actuation_qp(W, delta, Eigen::MatrixXd::Zero(1, 1), bounds, {{now, now, 0}}, 0.0);
  ASSERT_TRUE(c.solved) << c.status;
  EXPECT_EQ(now + c.dl(0), 0.0);
}

}  // namespace
