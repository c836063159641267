// Running a deck of input/ from a test: an output folder per tag inside the test's own
// folder (removed when the test ends, ../mpi_test_folder.hpp), and the summary shared with
// every rank.
#pragma once

#include <mpi.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "../mpi_test_decks.hpp"
#include "../mpi_test_folder.hpp"
#include "deck/deck.hpp"
#include "solvers/simulation.hpp"

namespace hs_test {

inline std::string out_folder(const std::string& tag) { return (test_folder() / tag).string(); }

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
  return shared(hs::run_simulation(hs::parse_deck(path, overrides), comm));
}

}  // namespace hs_test
