// Output of a run: every output step's fields written by every rank, its own rows, as HDF5 +
// XDMF into the run's staging folder, and its row of history.csv; finish() writes
// summary.json and commits the folder, keep_failed() keeps the steps of a failed run in
// "<folder>.failed" (docs/output.md).
#pragma once

#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "deck/config.hpp"
#include "io/output.hpp"
#include "io/step_history.hpp"
#include "solvers/constraints/constraint_set.hpp"
#include "solvers/problem.hpp"

namespace hs {

// Collective, before any work of the run: rank 0 opens the output folder (locks it, clears a
// crashed run's staging folder; OutputFolder) and gets it, the other ranks get null. When it
// cannot (another run is writing the folder, a foreign folder, a file-system error), every
// rank throws rank 0's message: InputError for the first two, std::runtime_error otherwise.
std::unique_ptr<OutputFolder> open_output_folder(const std::string& folder, MPI_Comm comm);

// This rank's rows of the output: its owned nodes and its tetrahedra (output.hpp).
OutputLayout output_layout(const Distribution& dist, MPI_Comm comm);

// What a history row holds after its `step`: the step's time under the name that says what
// it is, the Newton iterations since the previous row, then each source's columns.
struct HistorySources {
  std::string time_column = "load_factor";  // load_factor, time_s or state
  std::function<int()> newton_iterations;   // the run's total so far (none: no column)
  // Collective, called on every rank at every output step with the step's configuration.
  std::vector<std::function<void(Vec u, HistoryRow& row)>> columns;
};

// The reactions of the deck's boundary groups (Problem::reactions) at u and load factor s:
// history columns reaction_<group>_<x|y|z>_N, and summary.json's {group: [x, y, z]} (N).
// Collective.
void add_reactions(Problem& problem, Vec u, double s, HistoryRow& row);
nlohmann::json reactions_json(Problem& problem, Vec u, double s);
// The obstacles' contact (Problem::contact_totals) at u and load factor s: history columns
// contact_<obstacle>_<x|y|z>_N and contact_<obstacle>_area_m2, and summary.json's list of
// {obstacle, force_N: [x, y, z], area_m2} with the smallest gap. Collective; nothing
// without obstacles.
void add_contact(Problem& problem, Vec u, double s, HistoryRow& row);
nlohmann::json contact_json(Problem& problem, Vec u, double s);

class ResultRecorder {
 public:
  // folder: open_output_folder's result (null except on rank 0).
  ResultRecorder(Problem& problem, const Config& config, std::unique_ptr<OutputFolder> folder,
                 MPI_Comm comm);
  ~ResultRecorder();
  ResultRecorder(const ResultRecorder&) = delete;
  ResultRecorder& operator=(const ResultRecorder&) = delete;

  // Set before the first record().
  void set_history(HistorySources sources) { sources_ = std::move(sources); }
  // Writes the fields of u at `time` (the step's attribute), loads at load factor s, and the
  // step's history row. Collective; refuses (SolveError, nothing written) a step with a
  // non-finite value, and throws SolveError on every rank, naming the file and the reason,
  // when a file cannot be written.
  // time_kind: what `time` is in the .h5 and .xmf (docs/output.md); empty: the history's
  // time column (load_factor, time_s or state).
  void record(double time, Vec u, double s, const std::string& time_kind = "");
  // Decks with cavities: the constraints whose loads the steps split out of nodal_load.
  void set_constraints(const ConstraintSet* constraints) { constraints_ = constraints; }
  // Collective. Closes the files, writes the history into the .h5 and summary.json with
  // "status": "ok", and moves them to the output folder (rank 0); returns its path there.
  // When a file cannot be written (a full disk), throws SolveError on every rank with the
  // steps kept as by keep_failed (kept_in, kept_steps).
  std::string finish(nlohmann::json& summary);
  // Collective, after a failure (every rank): with at least one step written (or a
  // checkpoint), writes the history into the .h5 and summary.json (status "failed", the
  // reason, the last converged row) and renames the staging folder "<folder>.failed"; returns
  // that path (on every rank). Without either, returns "" and the staging folder goes with
  // the object. Never throws:
  // each part is tried on its own (on a full disk the rename still happens); rank 0 prints a
  // warning for summary.json or the rename when they fail, and "" is returned without the
  // rename.
  std::string keep_failed(nlohmann::json summary, const std::string& reason);
  std::string xdmf_path() const;
  // The staging folder the run writes into (every rank).
  const std::string& staging() const { return staging_; }
  // A restarted run: the Newton iterations before its first row, so that the first row
  // counts only its own.
  void set_newton_before(int iterations) { newton_at_last_row_ = iterations; }
  int written() const { return written_; }
  const StepHistory& history() const { return history_; }
  double seconds() const { return seconds_; }  // spent in record() and finish()

 private:
  std::vector<double> owned_values(Vec v) const;  // 3 per owned node
  void close_files();                             // the .xmf, and the history into the .h5
  Problem& problem_;
  MPI_Comm comm_;
  int rank_ = 0;
  int written_ = 0;
  double seconds_ = 0;
  std::unique_ptr<OutputFolder> folder_;
  std::unique_ptr<XdmfWriter> writer_;
  std::string staging_;  // every rank
  HistorySources sources_;
  StepHistory history_;
  int newton_at_last_row_ = 0;
  VecHandle load_;
  const ConstraintSet* constraints_ = nullptr;
};

}  // namespace hs
