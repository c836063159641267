// Output of a run: every output step's fields written by every rank, its own rows, as HDF5 +
// XDMF into the run's staging folder; finish() writes summary.json and commits the folder
// (docs/output.md).
#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "deck/config.hpp"
#include "io/output.hpp"
#include "solvers/problem.hpp"

namespace hs {

// Collective, before any work of the run: rank 0 opens the output folder (locks it, clears a
// crashed run's staging folder; OutputFolder) and gets it, the other ranks get null. When it
// cannot (another run is writing the folder, a foreign folder, a file-system error), every
// rank throws rank 0's message: InputError for the first two, std::runtime_error otherwise.
std::unique_ptr<OutputFolder> open_output_folder(const std::string& folder, MPI_Comm comm);

// This rank's rows of the output: its owned nodes and its tetrahedra (output.hpp).
OutputLayout output_layout(const Distribution& dist, MPI_Comm comm);

class ResultRecorder {
 public:
  // folder: open_output_folder's result (null except on rank 0).
  ResultRecorder(Problem& problem, const Config& config, std::unique_ptr<OutputFolder> folder,
                 MPI_Comm comm);
  ~ResultRecorder();
  ResultRecorder(const ResultRecorder&) = delete;
  ResultRecorder& operator=(const ResultRecorder&) = delete;

  // Writes the fields of u at `time` (the step's attribute), loads at load factor s.
  // Collective; refuses (SolveError, nothing written) a step with a non-finite value.
  void record(double time, Vec u, double s);
  // Closes the files and moves them to the output folder (rank 0); returns its path there.
  std::string finish(const nlohmann::json& summary);
  std::string xdmf_path() const;
  int written() const { return written_; }
  double seconds() const { return seconds_; }  // spent in record() and finish()

 private:
  std::vector<double> owned_values(Vec v) const;  // 3 per owned node
  Problem& problem_;
  int rank_ = 0;
  int written_ = 0;
  double seconds_ = 0;
  std::unique_ptr<OutputFolder> folder_;
  std::unique_ptr<XdmfWriter> writer_;
  Vec load_ = nullptr;
};

}  // namespace hs
