// The whole body on one rank beside a run on several: a training's full solves run on all
// ranks, and its model is built and checked on rank 0 (the reduced system answers on one
// rank, and POD and ECSW are serial), on a copy of the scene over MPI_COMM_SELF.
#pragma once

#include <Eigen/Dense>
#include <memory>
#include <vector>

#include "deck/config.hpp"
#include "mesh/distribution.hpp"
#include "solvers/constraints/constraint_set.hpp"
#include "solvers/effectors.hpp"
#include "solvers/problem.hpp"
#include "verification/exact_solution.hpp"

namespace hs {

struct WholeBody {
  // Loads the deck's mesh on this rank alone and makes its problem, constraints (in the
  // states `states`, those of the run beside it) and effectors.
  WholeBody(const Config& config, const std::vector<Constraint::State>& states);

  Distribution dist;
  std::unique_ptr<const ExactSolution> exact;
  std::unique_ptr<Problem> problem;
  std::unique_ptr<ConstraintSet> constraints;
  std::unique_ptr<Effectors> effectors;

  // Vectors of the mesh's dofs (3 * node number in the mesh file + d) in this body's local
  // order, the order of its PETSc vectors.
  std::vector<Eigen::VectorXd> local_order(const std::vector<Eigen::VectorXd>& in_mesh_order) const;
};

// Collective over `problem`'s ranks: each vector of owned values (a PETSc vector's local part)
// in the mesh's dof numbering on rank 0; empty elsewhere.
std::vector<Eigen::VectorXd> gather_in_mesh_order(const Problem& problem,
                                                  const std::vector<Eigen::VectorXd>& owned);

}  // namespace hs
