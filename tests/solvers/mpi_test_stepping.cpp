// Time and load stepping: Newmark conserves the total energy of a linear elastic body under
// a dead load (a conservation law the scheme must satisfy to round-off); backward Euler
// dissipates it; a quasi-static schedule that unloads ends on the exact solution of its
// last load factor.
#include <gtest/gtest.h>
#include <mpi.h>

#include <filesystem>
#include <string>

#include "deck/deck.hpp"
#include "run_deck.hpp"
#include "solvers/simulation.hpp"

namespace {

const std::string kSource = HYDROSOFT_SOURCE_DIR;

nlohmann::json run(const std::string& deck, const std::vector<std::string>& overrides,
                   const std::string& tag, MPI_Comm comm = MPI_COMM_WORLD) {
  return hs_test::run_deck(deck, overrides, "stepping_" + tag, comm);
}

TEST(Stepping, NewmarkConservesEnergy) {
  const auto s = run("cantilever_dynamic.yaml", {"time.end_time=2.0"}, "newmark");
  const double scale = s["energy"]["max_stored"].get<double>();
  EXPECT_GT(scale, 0.05);  // the beam really swung
  EXPECT_LT(s["energy"]["max_drift"].get<double>(), 1e-7 * scale);
  EXPECT_EQ(s["steps"].get<int>(), 20);
}

TEST(Stepping, BackwardEulerDissipatesEnergy) {
  const auto s = run("cantilever_dynamic.yaml",
                     {"time.end_time=2.0", "time.integrator=backward_euler"}, "euler");
  const double scale = s["energy"]["max_stored"].get<double>();
  EXPECT_LT(s["energy"]["final"].get<double>(), -0.2 * scale);
}

TEST(Stepping, QuasiStaticScheduleUnloads) {
  const auto s =
      run("bimaterial_bar.yaml",
          {"time.type=quasi_static", "time.steps=2", "time.schedule=[1.0, 0.25]"}, "schedule");
  EXPECT_EQ(s["steps"].get<int>(), 2);
  EXPECT_LT(s["error"]["l2_relative"].get<double>(), 1e-8);
}

}  // namespace
