// checkpoint.h5: what a run needs to continue from a converged step (docs/output.md,
// "Checkpoints and restarts"). Layout:
//   attributes of /: format = "hydrosoft checkpoint", version = 1, state = JSON text (the
//     step, the stepping's and the constraints' scalars, sizes, the deck's fingerprint)
//   /node_ids        N int64: each row's node number in the mesh file
//   /fields/<name>   N x 3 float64 (displacement, velocity, ...), rows as /node_ids
//   /series/<name>   K float64: per-step scalars of the run so far (a dynamic run's energies)
//   /element_ids     M int64: each element row's tetrahedron number in the mesh file, and
//   /element_fields/<name>  M float64 (an F-bar element's volume multiplier), where a run has
//     such fields
// Rows are in the writing run's solver numbering; a reader on any number of ranks places
// them by node (element) id. The file is written whole or not at all: into "<path>.tmp", renamed
// over <path> once closed, so a run killed while writing leaves the previous checkpoint intact.
#pragma once

#include <hdf5.h>
#include <mpi.h>

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "io/hdf5_file.hpp"

namespace hs {

// One rank's rows: [first, first + node_ids.size()) of `nodes`, and of the element fields'
// [first_element, first_element + element_ids.size()) of `elements`.
struct CheckpointRows {
  int64_t nodes = 0, first = 0;
  std::vector<int64_t> node_ids;
  int64_t elements = 0, first_element = 0;
  std::vector<int64_t> element_ids;
};

using NamedValues = std::vector<std::pair<std::string, std::vector<double>>>;

// Collective. fields: 3 values per row of this rank; series: rank 0's values (others empty);
// element_fields: 1 value per element row of this rank (the element rows are written with
// them only).
// When it cannot be written (a full disk), throws SolveError on every rank naming the file and
// the reason, with the unfinished .tmp removed and the previous checkpoint left whole.
void write_checkpoint(const std::string& path, MPI_Comm comm, const nlohmann::json& state,
                      const CheckpointRows& rows, const NamedValues& fields,
                      const NamedValues& series, const NamedValues& element_fields = {});

// Reading, each rank on its own (no collective calls). The file stays open for the object's
// life, so it can still be read after its folder was removed (an open file outlives its name).
class CheckpointFile {
 public:
  // Throws InputError naming the file when it is missing or not a hydrosoft checkpoint.
  explicit CheckpointFile(const std::string& path);
  CheckpointFile(const CheckpointFile&) = delete;
  CheckpointFile& operator=(const CheckpointFile&) = delete;

  const std::string& path() const { return path_; }
  const nlohmann::json& state() const { return state_; }
  int64_t nodes() const { return nodes_; }
  // Rows [begin, end): node ids, and 3 values per row of a field. InputError if unreadable.
  std::vector<int64_t> node_ids(int64_t begin, int64_t end) const;
  std::vector<double> field(const std::string& name, int64_t begin, int64_t end) const;
  std::vector<double> series(const std::string& name) const;  // empty if it is missing
  // The element rows (0 where the file has none), their ids and one field's values.
  int64_t elements() const { return elements_; }
  bool has_element_field(const std::string& name) const;
  std::vector<int64_t> element_ids(int64_t begin, int64_t end) const;
  std::vector<double> element_field(const std::string& name, int64_t begin, int64_t end) const;

 private:
  [[noreturn]] void fail(const std::string& reason) const;
  template <class T>
  std::vector<T> rows(const std::string& name, hid_t type, int64_t begin, int64_t end,
                      int cols) const;
  std::string path_;
  // A member handle, closed even when the constructor throws (an open file left behind made
  // HDF5 print "infinite loop closing library" at the process's end).
  Hdf5Handle file_{-1, H5Fclose};
  nlohmann::json state_;
  int64_t nodes_ = 0, elements_ = 0;
};

}  // namespace hs
