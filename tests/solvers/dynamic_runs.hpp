// Helpers of the dynamic cavity and cable tests: a small clamped silicone cylinder with one
// closed cavity (the cylinder of input/cylinder_air.yaml, coarser, in a linear law and without
// gravity), its decks run in the test's folder, and the history of a run read back.
#pragma once

#include <mpi.h>

#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "../mpi_test_decks.hpp"
#include "deck/deck.hpp"
#include "solvers/simulation.hpp"

namespace hs_test::dynamic_runs {

inline const std::string kBody = std::string("mesh:\n  file: ") + HYDROSOFT_SOURCE_DIR +
                                 "/meshes/cylinder.geo\n"
                                 "  order: 1\n"
                                 "  parameters: {R: 0.02, L: 0.15, t: 0.006, h: 0.015}\n"
                                 "materials:\n"
                                 "  - {group: body, model: linear_elastic, E: 2.0e5, nu: 0.45, "
                                 "density: 1070}\n"
                                 "boundary: [{group: top}]\n"
                                 "solver: {preset: mumps}\n";

// A run's summary and its history's columns (every rank gets rank 0's).
struct Trace {
  nlohmann::json summary;
  std::map<std::string, std::vector<double>> history;
  const std::vector<double>& operator[](const std::string& column) const {
    return history.at(column);
  }
};

// Runs body + text as deck `name` on comm: MPI_COMM_WORLD, or MPI_COMM_SELF on rank 0 alone
// (the others wait).
inline Trace simulate(const std::string& name, const std::string& text,
                      MPI_Comm comm = MPI_COMM_WORLD, const std::string& body = kBody) {
  const std::string folder = (test_folder() / (name + "_out")).string();
  const std::string path = write_deck(name + ".yaml", body + text);
  nlohmann::json result;
  if (comm == MPI_COMM_WORLD || world_rank() == 0) {
    const nlohmann::json summary = hs::run_simulation(
        hs::parse_deck(path, {"output.folder=" + folder, "output.progress=false"}), comm);
    if (world_rank() == 0) {
      result["summary"] = summary;
      std::ifstream csv(folder + "/history.csv");
      std::string line, cell;
      std::getline(csv, line);
      std::vector<std::string> columns;
      for (std::istringstream header(line); std::getline(header, cell, ',');)
        columns.push_back(cell);
      while (std::getline(csv, line)) {
        std::istringstream row(line);
        for (size_t c = 0; c < columns.size() && std::getline(row, cell, ','); ++c)
          result["history"][columns[c]].push_back(std::stod(cell));
      }
    }
  }
  MPI_Barrier(MPI_COMM_WORLD);
  result = shared(result);
  Trace trace;
  trace.summary = result["summary"];
  for (const auto& [column, values] : result["history"].items())
    trace.history[column] = values.get<std::vector<double>>();
  return trace;
}

// The cavity's entry of summary.json's end_of_run.
inline nlohmann::json end_cavity(const Trace& trace) {
  return trace.summary["end_of_run"]["cavities"][0];
}

// The mean of a sampled signal over its whole time span (trapezoidal).
inline double time_mean(const std::vector<double>& t, const std::vector<double>& x) {
  double integral = 0;
  for (size_t i = 1; i < t.size(); ++i) integral += 0.5 * (x[i] + x[i - 1]) * (t[i] - t[i - 1]);
  return integral / (t.back() - t.front());
}

}  // namespace hs_test::dynamic_runs
