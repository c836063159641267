// The inverse controller against forward simulations, on 1 and 2 ranks: a target that a
// forward run reaches with a known pressure is reached to 0.1 mm with that pressure, by the
// pneumatic and by the hydraulic cylinder (the liquid's weight acting through the unified
// constraint); a target beyond the pressure bound ends on the forward run at the bound, with
// the actuator marked saturated.
#include <gtest/gtest.h>
#include <petscsnes.h>

#include <cmath>
#include <filesystem>

#include "control_scene.hpp"
#include "solvers/inverse_controller.hpp"

namespace {

// A cylinder with its cavity as the actuator, the effector at the centre of the free end.
struct Scene : hs_test::ControlScene {
  Scene(const std::string& deck, double max_pressure)
      : ControlScene(deck, {0.0, 0.0, -0.15}, actuator(max_pressure)) {}
  static hs::ActuatorConfig actuator(double max_pressure) {
    hs::ActuatorConfig a;
    a.constraint = "cavity";
    a.max_multiplier = max_pressure;
    return a;
  }
};

void expect_reaches(const std::string& deck, const std::string& free_solve = "newton",
                    int refactor_every = 1) {
  Scene s(deck, 1e300);
  s.config.control->free_solve = hs::enum_of<hs::FreeSolve>(hs::kFreeSolveNames, free_solve);
  s.config.control->refactor_every = refactor_every;
  const double p = 3000;
  const auto target = s.forward(p);
  std::vector<double> x;  // the equilibrium at the final actuation (one_step reports a prediction)
  const hs::ControlStepReport r = s.drive(target, 8, &x);
  EXPECT_LT(r.error, 1e-4) << deck;
  double error2 = 0;
  for (int d = 0; d < 3; ++d) error2 += std::pow(x[d] - target[d], 2);
  EXPECT_LT(std::sqrt(error2), 1e-4) << deck << " " << free_solve << " " << refactor_every;
  EXPECT_NEAR(r.actuation[0], p, 0.01 * p) << deck;
  EXPECT_FALSE(r.saturated[0]);
  EXPECT_TRUE(r.qp_solved);
  EXPECT_LT(r.kkt_residual, 1e-8);
}

TEST(Control, PneumaticCylinderReachesAForwardRunsTarget) { expect_reaches("cylinder_air.yaml"); }

TEST(Control, HydraulicCylinderReachesAForwardRunsTarget) { expect_reaches("cylinder_water.yaml"); }

TEST(Control, OneLinearisationPerStepReachesTheTargetToo) {
  // The paper's real-time step (one assembly and factorization for the free motion and the
  // compliance), and the same with the factorization kept for three steps.
  expect_reaches("cylinder_water.yaml", "one_step", 1);
  expect_reaches("cylinder_water.yaml", "one_step", 3);
}

TEST(Control, UnreachableTargetSaturatesAtTheBound) {
  const double bound = 2000;
  Scene s("cylinder_air.yaml", bound);
  const auto at_bound = s.forward(bound);
  const auto beyond = s.forward(2.5 * bound);
  const hs::ControlStepReport r = s.drive(beyond, 8);
  EXPECT_NEAR(r.actuation[0], bound, 1e-6 * bound);
  EXPECT_TRUE(r.saturated[0]);
  for (int d = 0; d < 3; ++d) EXPECT_NEAR(r.reached[d], at_bound[d], 1e-4) << d;
  EXPECT_GT(r.error, 1e-3);  // the target really is out of reach
}

}  // namespace
