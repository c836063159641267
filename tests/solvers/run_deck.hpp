// Running a deck of input/ from a test: a private output folder per tag and world size (ctest
// runs the 1- and 2-rank variants at once), and the summary shared with every rank.
#pragma once

#include <mpi.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "deck/deck.hpp"
#include "solvers/simulation.hpp"

namespace hs_test {

inline std::string out_folder(const std::string& tag) {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  return (std::filesystem::temp_directory_path() /
          ("hydrosoft_" + tag + "_np" + std::to_string(size)))
      .string();
}

// Runs input/<deck> on `comm`. With MPI_COMM_WORLD every rank gets rank 0's summary; with
// MPI_COMM_SELF rank 0 runs it alone and the other ranks get null.
inline nlohmann::json run_deck(const std::string& deck, std::vector<std::string> overrides,
                               const std::string& tag, MPI_Comm comm = MPI_COMM_WORLD) {
  overrides.push_back("output.folder=" + out_folder(tag));
  const std::string path = std::string(HYDROSOFT_SOURCE_DIR) + "/input/" + deck;
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (comm != MPI_COMM_WORLD)
    return rank == 0 ? hs::run_simulation(hs::parse_deck(path, overrides), comm) : nlohmann::json();
  std::string text = hs::run_simulation(hs::parse_deck(path, overrides), comm).dump();
  int n = static_cast<int>(text.size());
  MPI_Bcast(&n, 1, MPI_INT, 0, MPI_COMM_WORLD);
  text.resize(n);
  MPI_Bcast(text.data(), n, MPI_CHAR, 0, MPI_COMM_WORLD);
  return nlohmann::json::parse(text);
}

}  // namespace hs_test
