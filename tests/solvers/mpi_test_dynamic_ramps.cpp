// Dynamics with cavities and cables (solvers/stepping/dynamic_states_stepper.hpp) on 1 and 2
// ranks: a ramp slow against the body's periods ends where the quasi-static states run of the
// same deck does, under a pressure and under a volume; a tendon pulled suddenly balances its
// work (tension times pull) with the body's kinetic and stored energy; a time step whose solve
// fails is taken again in the sub-steps a shorter time step would take.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/error.hpp"
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

// The cylinder in a neo-Hookean law, inflated suddenly to 40 kPa in one time step of 20 ms:
// the solve fails at that step (an element inverts), and the step is taken again in 2, 4, ...
// sub-steps until 32 converge. That is the run a time step of 20/32 ms takes: the same end to
// round-off, its energy balance (the work accumulated sub-step by sub-step) included.
TEST(DynamicCutback, AFailedTimeStepIsTakenInTheStepsOfAShorterOne) {
  std::string body = kBody;
  body.replace(body.find("linear_elastic"), 14, "neo_hookean");
  const std::string cavity =
      "cavities: [{group: cavity, pressure: 40000}]\nstates: [{name: inflate, time: 0.02}]\n";
  const Trace cut =
      simulate("cutback", cavity + "time: {type: dynamic, dt: 0.02, end_time: 0.02}\n",
               MPI_COMM_WORLD, body);
  const Trace fine =
      simulate("cutback_fine", cavity + "time: {type: dynamic, dt: 0.000625, end_time: 0.02}\n",
               MPI_COMM_WORLD, body);
  EXPECT_EQ(cut.summary["cutbacks"], 5);
  EXPECT_EQ(fine.summary["cutbacks"], 0);
  const double v_cut = end_cavity(cut)["volume"], v_fine = end_cavity(fine)["volume"];
  EXPECT_NEAR(v_cut, v_fine, 1e-9 * v_fine);
  for (const char* key : {"stored_final", "kinetic_final", "final"})
    EXPECT_NEAR(cut.summary["energy"][key].get<double>(), fine.summary["energy"][key].get<double>(),
                1e-9 * fine.summary["energy"]["stored_final"].get<double>())
        << key;
  EXPECT_NEAR(cut.summary["energy"]["work_J"]["cavity"].get<double>(),
              fine.summary["energy"]["work_J"]["cavity"].get<double>(),
              1e-9 * fine.summary["energy"]["work_J"]["cavity"].get<double>());
  // Without cutbacks the step fails, and says how many halvings it was allowed.
  try {
    simulate("no_cutback",
             cavity + "time: {type: dynamic, dt: 0.02, end_time: 0.02, max_cutbacks: 0}\n",
             MPI_COMM_WORLD, body);
    ADD_FAILURE() << "the step converged without cutbacks";
  } catch (const hs::SolveError& e) {
    EXPECT_NE(std::string(e.what()).find("after 0 halvings of the time step (time.max_cutbacks)"),
              std::string::npos)
        << e.what();
  }
}

// The same for a body without cavities (solvers/stepping/dynamic_stepper.hpp): a soft
// neo-Hookean cantilever dropped under its weight in one step of 0.5 s (two halvings) ends
// where four steps of 0.125 s do.
TEST(DynamicCutback, AFailedTimeStepOfAPlainBodyToo) {
  const std::string body =
      std::string("mesh: {file: ") + HYDROSOFT_SOURCE_DIR +
      "/meshes/cantilever.geo, order: 1, parameters: {L: 1.0, h: 0.1}}\n"
      "materials: [{group: body, model: neo_hookean, E: 3.0e5, nu: 0.3, density: 1000}]\n"
      "boundary: [{group: clamped}]\nloads: {gravity: [0, 0, -9.81]}\nsolver: {preset: mumps}\n";
  const Trace cut = simulate("plain_cutback", "time: {type: dynamic, dt: 0.5, end_time: 0.5}\n",
                             MPI_COMM_WORLD, body);
  const Trace fine = simulate("plain_fine", "time: {type: dynamic, dt: 0.125, end_time: 0.5}\n",
                              MPI_COMM_WORLD, body);
  EXPECT_EQ(cut.summary["cutbacks"], 2);
  const double stored = fine.summary["energy"]["max_stored"];
  EXPECT_GT(stored, 1.0);
  EXPECT_NEAR(cut.summary["energy"]["final"].get<double>(),
              fine.summary["energy"]["final"].get<double>(), 1e-9 * stored);
  for (int d = 0; d < 3; ++d)  // the clamp's reaction: the weight and the inertia at the end
    EXPECT_NEAR(cut.summary["reactions_N"]["clamped"][d].get<double>(),
                fine.summary["reactions_N"]["clamped"][d].get<double>(), 1e-8 * 171.6)
        << d;
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
