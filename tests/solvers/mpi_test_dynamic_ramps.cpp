// Dynamics with cavities and cables (solvers/stepping/dynamic_states_stepper.hpp) on 1 and 2
// ranks: a ramp slow against the body's periods ends where the quasi-static states run of the
// same deck does, under a pressure and under a volume; a tendon pulled suddenly balances its
// work (tension times pull) with the body's kinetic and stored energy.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "dynamic_runs.hpp"

namespace {
namespace mpi_test_dynamic_ramps {

using namespace hs_test::dynamic_runs;

// Over 0.1 s, 40 periods of the cavity's breathing mode (2.5 ms); output every 10 steps.
const std::string kRamp = "states: [{name: inflate, time: 0.1}]\noutput: {every: 10}\n";
const std::string kTime = "time: {type: dynamic, dt: 0.001, end_time: 0.1}\n";

TEST(DynamicRamp, SlowPressureRampEndsAtTheQuasiStaticVolume) {
  const std::string cavity = "cavities: [{group: cavity, pressure: 300}]\n";
  const double v_static = end_cavity(simulate("pressure_static", cavity))["volume"];
  const Trace r = simulate("pressure_ramp", cavity + kRamp + kTime);
  const double v0 = r["cavity_cavity_volume_m3"].front(), change = v_static - v0;
  const nlohmann::json& state = r.summary["states"][0]["cavities"][0];
  const double reached = state["volume"].get<double>() - v0;
  std::printf("pressure ramp: volume change %.5f of the quasi-static one\n", reached / change);
  EXPECT_EQ(r.summary["states"][0]["time"], 0.1);
  EXPECT_EQ(state["pressure"], 300);
  EXPECT_NEAR(reached, change, 0.005 * change);
  EXPECT_LT(r.summary["energy"]["max_drift"].get<double>(),
            1e-6 * r.summary["energy"]["max_stored"].get<double>());
}

TEST(DynamicRamp, SlowVolumeRampEndsAtTheQuasiStaticPressure) {
  // Under a volume control Newmark's trapezoidal rule leaves the pressure swinging from step to
  // step (docs/cavities.md, "Dynamics"): gamma > 1/2 damps that.
  const std::string cavity = "cavities: [{group: cavity, added_volume: 3.6e-7}]\n";
  const double p_static = end_cavity(simulate("volume_static", cavity))["pressure"];
  const Trace r = simulate("volume_ramp", cavity + kRamp +
                                              "time: {type: dynamic, dt: 0.001, end_time: 0.1, "
                                              "newmark: {beta: 0.3025, gamma: 0.6}}\n");
  const nlohmann::json& state = r.summary["states"][0]["cavities"][0];
  std::printf("volume ramp: pressure %.3f Pa, quasi-static %.3f Pa\n",
              state["pressure"].get<double>(), p_static);
  EXPECT_GT(p_static, 250);
  EXPECT_NEAR(state["pressure"].get<double>(), p_static, 0.005 * p_static);
  // Added volumes count from the end of the first state, which this one is.
  EXPECT_EQ(state["added_volume_ml"].get<double>(), 0);
  EXPECT_NEAR(r.summary["states"][0]["volume_change_ml"].get<double>(), 0.36, 1e-8);
}

TEST(DynamicCable, SuddenTensionBalancesItsWork) {
  // A straight tendon inside the wall, from the free end cap to a pull point above the clamp,
  // pulled with 0.05 N from t = 0.
  const std::string cable =
      "cables: [{name: tendon, points: [[0, -0.017, -0.02], [0, -0.017, -0.08], [0, -0.017, "
      "-0.146]], pull_point: [0, -0.017, 0.03], force: 0.05}]\n";
  const Trace r = simulate("cable_step", cable +
                                             "time: {type: dynamic, dt: 0.0005, end_time: 0.03}\n"
                                             "output: {every: 2}\n");
  // The pull counts from the end of the first state: here t = 0, the undeformed body; the
  // static run's is its pulled equilibrium, so it is compared by the cable's length.
  const nlohmann::json end = r.summary["end_of_run"]["cables"][0];
  const double rest_length = end["length"].get<double>() + end["pull"].get<double>();
  const double static_pull =
      rest_length -
      simulate("cable_static", cable).summary["end_of_run"]["cables"][0]["length"].get<double>();
  const std::vector<double>& pull = r["cable_tendon_pull_m"];
  const double peak = *std::max_element(pull.begin(), pull.end());
  const nlohmann::json& energy = r.summary["energy"];
  std::printf("tendon: peak pull %.4f x the static one; energy drift %.3e J of %.3e J\n",
              peak / static_pull, energy["max_drift"].get<double>(),
              energy["max_stored"].get<double>());
  ASSERT_GT(static_pull, 0);
  EXPECT_LE(peak, 2 * static_pull * (1 + 1e-3));
  EXPECT_GE(peak, 1.1 * static_pull);  // the bending mode (45 ms) halfway
  EXPECT_NEAR(energy["work_J"]["tendon"].get<double>(), 0.05 * pull.back(), 1e-9 * 0.05 * peak);
  EXPECT_LT(energy["max_drift"].get<double>(), 1e-6 * energy["max_stored"].get<double>());
}

}  // namespace mpi_test_dynamic_ramps
}  // namespace
