// The pressure-limited cavity (solvers/constraints/pressure_limited_cavity.hpp) on 1 and 2
// ranks, against the pneumatic cavity it becomes on either side of its valve: with the valve
// open it is the cavity at max_pressure, with the valve shut the cavity that holds the
// delivered volume.
#include <gtest/gtest.h>

#include "run_deck.hpp"

namespace {

const std::string kFill = "states=[{name: fill, steps: 4}]";

// The coarse compressible cylinder (../mpi_test_decks.hpp) with the given cavity.
nlohmann::json end_of(const std::string& cavity, const std::string& tag) {
  return hs_test::run_deck("cylinder_air.yaml",
                           hs_test::coarse_cylinder({kFill, "cavities[0]=" + cavity}),
                           tag)["end_of_run"]["cavities"][0];
}

}  // namespace

TEST(PressureLimitedCavity, PastItsLimitItIsTheCavityAtThatPressure) {
  // The pneumatic cylinder reaches 7.95 kPa with 15 ml added: a valve at 5 kPa opens.
  const auto limited = end_of(
      "{group: cavity, kind: pressure_limited, added_volume: 1.5e-5, max_pressure: 5000}", "open");
  const auto at_limit = end_of("{group: cavity, pressure: 5000}", "at_limit");
  EXPECT_EQ(limited["kind"], "pressure_limited");
  EXPECT_NEAR(limited["pressure"].get<double>(), 5000, 1e-9 * 5000);
  const double v = at_limit["volume"].get<double>();
  EXPECT_NEAR(limited["volume"].get<double>(), v, 1e-9 * v);
  EXPECT_TRUE(limited["valve_open"].get<bool>());
  // What the pump delivered and the cavity does not hold has left through the valve.
  const double delivered = limited["delivered_volume"].get<double>();
  EXPECT_GT(limited["vented_volume"].get<double>(), 1e-6);
  EXPECT_NEAR(limited["vented_volume"].get<double>(), delivered - limited["volume"].get<double>(),
              1e-12 * delivered);
}

TEST(PressureLimitedCavity, BelowItsLimitItHoldsWhatThePumpDelivered) {
  const auto limited = end_of(
      "{group: cavity, kind: pressure_limited, added_volume: 1.5e-5, max_pressure: 1e6}", "shut");
  const auto pumped = end_of("{group: cavity, added_volume: 1.5e-5}", "pumped");
  const double p = pumped["pressure"].get<double>(), v = pumped["volume"].get<double>();
  EXPECT_GT(p, 7000);
  EXPECT_NEAR(limited["pressure"].get<double>(), p, 1e-8 * p);
  EXPECT_NEAR(limited["volume"].get<double>(), v, 1e-12 * v);
  EXPECT_NEAR(limited["delivered_volume"].get<double>(), v, 1e-12 * v);
  EXPECT_FALSE(limited["valve_open"].get<bool>());
  EXPECT_EQ(limited["vented_volume"].get<double>(), 0.0);
}
