// The offline part of a reduced model (docs/reduced_models.md): from displacement snapshots of
// the full model to the model's basis (POD) and sampled elements (ECSW), one rank.
#pragma once

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "deck/config.hpp"
#include "reduction/model_file.hpp"
#include "solvers/problem.hpp"

namespace hs {

// training: local dofs x snapshots. Sets model.basis (mesh numbering), elements and weights,
// and the report's `pod` and `ecsw` entries (sizes, criteria, seconds).
void build_reduced_model(const Problem& problem, const Eigen::MatrixXd& training,
                         const TrainingConfig& settings, ReducedModel& model);

}  // namespace hs
