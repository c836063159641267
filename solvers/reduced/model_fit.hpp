// Whether a reduced model (reduction/model_file.hpp) belongs to a run: the checks a model
// file passes before any work, and what the training records for them.
#pragma once

#include <string>

#include "deck/config.hpp"
#include "reduction/model_file.hpp"
#include "solvers/constraints/constraint_set.hpp"
#include "solvers/problem.hpp"

namespace hs {

// The deck's physics as a fingerprint (deck/config_fingerprint.hpp) of the sections that
// decide the equilibrium at a given actuation: mesh, materials, boundary, loads, cavities,
// cables, obstacles. Effectors, targets, states, the solver and the output may differ.
std::string reduced_physics(const Config& config);

// The mesh's record in a model: sizes, order, coordinate checksum (one rank: the whole mesh).
void record_mesh(const Problem& problem, ReducedModel& model);

// Throws InputError naming `path` and the reason when the model does not belong to the run or
// the run is one a reduced model cannot answer (docs/reduced_models.md, "Limits").
void check_model_fits(const Config& config, const Problem& problem,
                      const ConstraintSet& constraints, const ReducedModel& model,
                      const std::string& path);

// The same limits for a training run (before any work), naming the deck.
void check_reducible(const Config& config, const Problem& problem,
                     const ConstraintSet& constraints);

}  // namespace hs
