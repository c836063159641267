// The history of a run: one row per output step (its index, its load factor, time or state,
// Newton iterations, and what the scene has: cavities, cables, effectors, actuators), kept as
// <folder>/history.csv, appended after every step so that a run in progress or one that died
// has it too, and as /history/<column> datasets of the .h5 when the run ends (docs/output.md).
#pragma once

#include <mpi.h>

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

namespace hs {

// One row: (column, value) in the order the columns are added.
struct HistoryRow {
  struct Cell {
    std::string column;
    double value = 0;
    bool integer = false;  // a count or an index: int64 in the .h5 and in JSON
  };
  std::vector<Cell> cells;
  // `name` becomes a column name: characters other than letters, digits, '_', '-' and '.'
  // become '_' (a CSV header and an HDF5 dataset name need no quoting then).
  void add(const std::string& name, double value);
  void add_count(const std::string& name, int64_t value);
};

class StepHistory {
 public:
  // Every row has the columns of the first (std::logic_error otherwise). With a path, the
  // row is appended to that CSV file (the header first) and the file closed; a write that
  // fails throws std::runtime_error naming the file and the reason, and leaves the file as
  // it was (never half a row). The row is kept here either way.
  void append(const HistoryRow& row, const std::string& csv_path = "");
  const std::vector<std::string>& columns() const { return columns_; }
  size_t rows() const { return values_.size(); }
  std::vector<double> column(size_t c) const;
  // The last row as {column: value}; null without rows.
  nlohmann::json last_row() const;
  // Collective when comm is not null: /history/<column> (float64, one entry per row) in the
  // HDF5 file at h5_path (int64 for counts and indices), written by rank 0 (every rank holds
  // the same rows).
  void write_h5(const std::string& h5_path, MPI_Comm comm) const;

 private:
  std::vector<std::string> columns_;
  std::vector<bool> integer_;
  std::vector<std::vector<double>> values_;
};

}  // namespace hs
