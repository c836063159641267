// What a run writes beside its fields (solvers/simulation.cpp): the columns of its history,
// the timings and sizes of summary.json, and, when it fails, its converged steps kept.
#pragma once

#include <mpi.h>

#include <nlohmann/json.hpp>

#include "common/error.hpp"
#include "deck/config.hpp"
#include "mesh/distribution.hpp"
#include "solvers/constraints/constraint_set.hpp"
#include "solvers/distributed_mesh.hpp"
#include "solvers/output/result_recorder.hpp"
#include "solvers/problem.hpp"
#include "solvers/stepping.hpp"

namespace hs {

// The history's columns (docs/output.md): the time under the name of what it is (state in a
// scene with constraints, else time_s or load_factor), the Newton iterations of the stepping
// (a control run's stepper adds those of its control steps, and its effectors and actuators:
// Stepper::add_history), the cavities and cables (ConstraintSet::add_history). constraints
// may be null.
HistorySources history_sources(const Config& config, bool staged, ConstraintSet* constraints,
                               const SteppingStats& stats);

// summary.json's time_s (assembly, output, the set-up's parts; slowest rank), mesh shares,
// memory_mb and assembly rates. Collective.
void add_timings(nlohmann::json& summary, const Problem& problem, const Distribution& dist,
                 const MeshLoadTimes& mesh_times, const ResultRecorder& recorder, MPI_Comm comm);

// Collective, every rank with the same error: keeps the steps written so far in
// "<folder>.failed" with summary.json saying why (ResultRecorder::keep_failed) and notes
// where in the error (kept_in, kept_steps). A failure to keep them is printed, not thrown:
// the run's own error is the one the user must see (ResultRecorder::keep_failed).
void keep_converged_steps(SolveError& error, ResultRecorder& recorder, nlohmann::json summary,
                          MPI_Comm comm);

}  // namespace hs
