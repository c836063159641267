// Helpers of the MPI tests that write their own decks and run them: the world's rank and
// size, a deck written into the test's folder (and the paper's cylinder as the tests of
// mechanisms run it, pinned_decks.hpp), rank 0's summary on every rank, and a whole dataset of a
// run's .h5 file, and its history.csv.
#pragma once

#include <hdf5.h>
#include <mpi.h>

#include <cstdlib>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "mpi_test_folder.hpp"
#include "pinned_decks.hpp"

namespace hs_test {

inline int world_rank() {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
}

inline int world_size() {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  return size;
}

// Writes a deck into the test's folder (rank 0) and returns its path on every rank.
inline std::string write_deck(const std::string& name, const std::string& text) {
  const std::string path = (test_folder() / name).string();
  if (world_rank() == 0) std::ofstream(path) << text;
  MPI_Barrier(MPI_COMM_WORLD);
  return path;
}

// Rank 0's summary on every rank.
inline nlohmann::json shared(const nlohmann::json& summary) {
  std::string text = world_rank() == 0 ? summary.dump() : std::string();
  int n = static_cast<int>(text.size());
  MPI_Bcast(&n, 1, MPI_INT, 0, MPI_COMM_WORLD);
  text.resize(n);
  MPI_Bcast(text.data(), n, MPI_CHAR, 0, MPI_COMM_WORLD);
  return nlohmann::json::parse(text);
}

// A whole dataset of an .h5 file, as doubles (read by the calling rank alone).
inline std::vector<double> read_dataset(const std::string& path, const std::string& name) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t set = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  const hid_t space = H5Dget_space(set);
  std::vector<double> v(H5Sget_simple_extent_npoints(space));
  H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  H5Sclose(space);
  H5Dclose(set);
  H5Fclose(file);
  return v;
}

// A run's history.csv as {column: values by row}, a state's name read as 0 (read by the
// calling rank alone).
inline std::map<std::string, std::vector<double>> read_history(const std::string& folder) {
  std::ifstream in(folder + "/history.csv");
  std::string header, line, cell;
  std::getline(in, header);
  std::vector<std::string> names;
  for (std::stringstream h(header); std::getline(h, cell, ',');) names.push_back(cell);
  std::map<std::string, std::vector<double>> columns;
  while (std::getline(in, line)) {
    std::stringstream values(line);
    for (size_t c = 0; c < names.size() && std::getline(values, cell, ','); ++c)
      columns[names[c]].push_back(std::strtod(cell.c_str(), nullptr));  // a name: 0
  }
  return columns;
}

}  // namespace hs_test
