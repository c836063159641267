// Dynamics with cavities (solvers/stepping/dynamic_states_stepper.hpp) on 1 and 2 ranks,
// against references that do not come from it: the static run of the same deck; the bound of
// a suddenly applied pressure (each mode of a linear body swings from rest to twice its static
// share and back, and every mode's share of the cavity's volume change is positive, so the
// change stays within twice the static one and averages to it); the energy balance; the
// deck's schedule; the same run on one rank.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "dynamic_runs.hpp"

namespace {
namespace mpi_test_dynamic_cavities {

using namespace hs_test::dynamic_runs;

const std::string kSudden = "cavities: [{group: cavity, pressure: 300}]\n";  // 0.5 % of V
const std::string kNewmark = "time: {type: dynamic, dt: 0.0005, end_time: 0.03}\n";

// Run once (on every rank, by the first test that asks).
double static_volume() {
  static const double volume =
      end_cavity(simulate("static", kSudden + "time: {type: static}\n"))["volume"];
  return volume;
}

TEST(DynamicCavity, SuddenPressureSwingsAboutTheStaticVolume) {
  const double v_static = static_volume();
  const Trace r = simulate("sudden", kSudden + kNewmark);
  const std::vector<double>& v = r["cavity_cavity_volume_m3"];
  const double v0 = v.front(), change = v_static - v0;
  const double peak = *std::max_element(v.begin(), v.end()) - v0;
  const double mean = time_mean(r["time_s"], v) - v0;
  const nlohmann::json& energy = r.summary["energy"];
  std::printf("static change %.6e m3: peak %.4f x, mean %.4f x; energy drift %.3e J of %.3e J\n",
              change, peak / change, mean / change, energy["max_drift"].get<double>(),
              energy["max_stored"].get<double>());
  ASSERT_GT(change, 0);
  EXPECT_LE(peak, 2.0 * change * (1 + 1e-3));
  EXPECT_GE(peak, 1.8 * change);
  EXPECT_NEAR(mean, change, 0.02 * change);  // 12 periods of the breathing mode (2.5 ms)
  for (double p : r["cavity_cavity_pressure_Pa"]) EXPECT_EQ(p, 300);  // held from t = 0
  // Newmark's trapezoidal rule keeps kinetic + stored - p (V - V0), up to V's curvature.
  EXPECT_LT(energy["max_drift"].get<double>(), 1e-6 * energy["max_stored"].get<double>());
  EXPECT_NEAR(energy["work_J"]["cavity"].get<double>(), 300 * (v.back() - v0), 1e-9 * 300 * change);
  EXPECT_EQ(r.summary["states"].size(), 1u);
  EXPECT_EQ(r.summary["states"][0]["step"], 0);  // the first state is reached at t = 0
}

TEST(DynamicCavity, BackwardEulerDissipatesAndSettles) {
  const double v_static = static_volume();
  const Trace r = simulate("euler", kSudden +
                                        "time: {type: dynamic, dt: 0.0005, end_time: "
                                        "0.03, integrator: backward_euler}\n"
                                        "output: {every: 2}\n");
  const std::vector<double>& v = r["cavity_cavity_volume_m3"];
  const double v0 = v.front(), change = v_static - v0;
  const double peak = *std::max_element(v.begin(), v.end()) - v0;
  const nlohmann::json& energy = r.summary["energy"];
  std::printf("backward Euler: peak %.4f x, end %.4f x; energy %.3e J of %.3e J\n", peak / change,
              (v.back() - v0) / change, energy["final"].get<double>(),
              energy["max_stored"].get<double>());
  EXPECT_LT(peak, 1.5 * change);
  EXPECT_NEAR(v.back() - v0, change, 0.02 * change);
  // The energy only falls, and by the end most of what the swing held is gone.
  const std::vector<double>& e = r["energy_J"];
  for (size_t i = 1; i < e.size(); ++i)
    EXPECT_LE(e[i], e[i - 1] + 1e-12 * energy["max_stored"].get<double>());
  EXPECT_LT(energy["final"].get<double>(), -0.3 * energy["max_stored"].get<double>());
}

TEST(DynamicCavity, TheStatesAreASchedule) {
  // 300 Pa ramped in over 5 ms, then released at once: the pressure of every step is the
  // schedule's, and the work is the trapezoidal sum of p dV over the history's steps.
  const Trace r = simulate("schedule",
                           "cavities: [{group: cavity}]\n"
                           "states:\n  - {name: rest}\n"
                           "  - {name: up, time: 0.005, cavities: {cavity: {pressure: 300}}}\n"
                           "  - {name: down, time: 0.005, cavities: {cavity: {pressure: 0}}}\n"
                           "time: {type: dynamic, dt: 0.0005, end_time: 0.02}\n");
  const std::vector<double>& t = r["time_s"];
  const std::vector<double>& p = r["cavity_cavity_pressure_Pa"];
  const std::vector<double>& v = r["cavity_cavity_volume_m3"];
  ASSERT_EQ(t.size(), 41u);
  for (size_t i = 0; i < t.size(); ++i) {
    const double expected = i <= 10 ? 300 * t[i] / 0.005 : 0.0;
    EXPECT_NEAR(p[i], expected, 1e-9) << "t = " << t[i];
  }
  const nlohmann::json& states = r.summary["states"];
  ASSERT_EQ(states.size(), 3u);
  const double times[] = {0, 0.005, 0.0055};
  const int steps[] = {0, 10, 11};
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(states[k]["time"].get<double>(), times[k], 1e-15);
    EXPECT_EQ(states[k]["step"], steps[k]);
  }
  double work = 0;
  for (size_t i = 1; i < t.size(); ++i) work += 0.5 * (p[i] + p[i - 1]) * (v[i] - v[i - 1]);
  const nlohmann::json& energy = r.summary["energy"];
  EXPECT_NEAR(energy["work_J"]["cavity"].get<double>(), work, 1e-12 * std::abs(work));
  EXPECT_LT(energy["max_drift"].get<double>(), 1e-4 * energy["max_stored"].get<double>());
  // After the release nothing works on the body: its energy is kinetic + stored.
  const std::vector<double>& e = r["energy_J"];
  EXPECT_NEAR(e.back(), r["kinetic_energy_J"].back() + r["stored_energy_J"].back() - work,
              1e-12 * energy["max_stored"].get<double>());
}

TEST(DynamicCavity, SameOnOneAndTwoRanks) {
  if (hs_test::world_size() != 2) GTEST_SKIP() << "compares 2 ranks with 1";
  const std::string deck = kSudden + "time: {type: dynamic, dt: 0.0005, end_time: 0.01}\n";
  const Trace two = simulate("two", deck), one = simulate("one", deck, MPI_COMM_SELF);
  const std::vector<double>&v1 = one["cavity_cavity_volume_m3"],
        &v2 = two["cavity_cavity_volume_m3"];
  ASSERT_EQ(v1.size(), v2.size());
  const double scale = v1.back() - v1.front();
  double worst = 0;
  for (size_t i = 0; i < v1.size(); ++i) worst = std::max(worst, std::abs(v1[i] - v2[i]) / scale);
  std::printf("1 and 2 ranks: volume change differs by %.2e of it at most\n", worst);
  EXPECT_LT(worst, 1e-8);
  const std::vector<double>&e1 = one["energy_J"], &e2 = two["energy_J"];
  for (size_t i = 0; i < e1.size(); ++i)
    EXPECT_NEAR(e1[i], e2[i], 1e-8 * one.summary["energy"]["max_stored"].get<double>());
}

}  // namespace mpi_test_dynamic_cavities
}  // namespace
