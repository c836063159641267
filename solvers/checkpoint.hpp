// Checkpoints and restarts (docs/output.md, "Checkpoints and restarts"). At a step boundary
// the stepping hands the Checkpointer its position (a JSON object of scalars) and its nodal
// vectors; it writes checkpoint.h5 into the run's staging folder (io/checkpoint_file.hpp)
// when output.checkpoint says one is due. `hydrosoft DECK --restart FOLDER` makes a Restart
// from FOLDER/checkpoint.h5 before the output folder is opened, checks that it was written
// by this deck on this mesh, and the stepping continues from its position. Static and
// quasi-static load stepping, dynamic runs, the states of cavity and cable decks and the
// target sets of a batch control run are covered; the interactive mode (--targets -) is not
// (check_checkpoint_use refuses it).
#pragma once

#include <mpi.h>
#include <petscvec.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "deck/config.hpp"
#include "io/checkpoint_file.hpp"
#include "solvers/constraints/constraint_set.hpp"
#include "solvers/problem.hpp"
#include "solvers/stepping.hpp"

namespace hs {

using NamedVecs = std::vector<std::pair<std::string, Vec>>;

// What kind of stepping a deck runs: "static" (and quasi-static), "dynamic", "states" or
// "control" (its states, then its target sets).
std::string stepping_kind(const Config& config);

// Throws InputError (naming the key and the reason) where a checkpoint or a restart does not
// apply: the interactive control mode, whose targets come from a client that a restart cannot
// take back to where the run stopped.
void check_checkpoint_use(const Config& config, bool restart);

class Checkpointer {
 public:
  // folder: the run's staging folder (the same path on every rank). Inactive without
  // output.checkpoint.
  Checkpointer(const Config& config, const Problem& problem, const SteppingStats& stats,
               std::string folder, MPI_Comm comm);
  bool active() const { return active_; }
  // Collective, after every converged step: counts it and says whether a checkpoint is due
  // (output.checkpoint's steps or minutes since the last, or a signal that stops the run).
  bool due(bool signal);
  // Counts the steps (and minutes) from here: the control loop counts target sets.
  void start_count();
  // Collective: writes <folder>/checkpoint.h5 (atomically) with `position`, the run's
  // header (sizes, fingerprint, stats) and the owned rows of `fields`; series: rank 0's;
  // element_fields: a value per local tetrahedron (in the order of the distribution's).
  void write(nlohmann::json position, const NamedVecs& fields, const NamedValues& series = {},
             const NamedValues& element_fields = {});
  int written() const { return written_; }

 private:
  const Config& config_;
  const Problem& problem_;
  const SteppingStats& stats_;
  std::string path_;
  MPI_Comm comm_;
  bool active_ = false;
  int steps_since_ = 0, written_ = 0;
  double last_time_ = 0;
};

class Restart {
 public:
  // Collective, before the output folder is opened (which may clear FOLDER when it is that
  // folder's .partial: the file stays open and readable). Throws InputError on every rank,
  // naming the file and the reason, when it is missing, not a checkpoint, of another deck, or
  // holds a field out of its kind or range (check_checkpoint_state).
  Restart(const std::string& folder, const Config& config, MPI_Comm comm);
  // Collective, once the problem exists: refuses a checkpoint of another mesh (node count,
  // element count, order, node coordinates).
  void check_mesh(const Problem& problem) const;
  // The stepping's position as the Checkpointer was given it.
  const nlohmann::json& position() const { return file_->state().at("position"); }
  // Collective: this rank's owned rows of a field, placed by node id.
  void read(const std::string& name, const Problem& problem, Vec v) const;
  // Collective: a value per local tetrahedron of an element field, placed by element id; empty
  // where the checkpoint has no such field (one of an older run).
  std::vector<double> read_elements(const std::string& name, const Problem& problem) const;
  std::vector<double> series(const std::string& name) const { return file_->series(name); }
  // The step counts of the run so far.
  void restore(SteppingStats& stats) const;
  // summary.json's restarted_from.
  nlohmann::json summary() const;

 private:
  std::unique_ptr<CheckpointFile> file_;
  std::string folder_;
  MPI_Comm comm_;
};

// Throws InputError "--restart: FILE: KEY: reason" unless `state` (a checkpoint's, read from
// FILE) was written by this deck (its kind of stepping and its fingerprint) and every field
// that a restart reads back has its kind and lies in its range for this deck: the step, state,
// increment or target set within the deck's, `last` true exactly at the last one, the load
// factor or time of that step, as many constraints, ramps and actuators as the deck has (the
// constraints by name), counts from 0, finite numbers. A checkpoint of the run's last step is
// refused too (nothing is left to run).
void check_checkpoint_state(const nlohmann::json& state, const Config& config,
                            const std::string& file);

// Each constraint's state (multiplier, target, control, measures), and the same put back.
nlohmann::json constraint_states(const ConstraintSet& constraints);
void restore_constraint_states(ConstraintSet& constraints, const nlohmann::json& states);

}  // namespace hs
