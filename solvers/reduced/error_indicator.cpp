#include "solvers/reduced/error_indicator.hpp"

#include <petscksp.h>

#include <cmath>

#include "common/error.hpp"
#include "solvers/petsc_check.hpp"

namespace hs {
ResidualErrorIndicator::ResidualErrorIndicator(Problem& problem, ConstraintSet& constraints,
                                               const ReducedSystem& system,
                                               const std::vector<int>& actuators,
                                               const std::vector<Vec>& rows)
    : constraints_(constraints), system_(system), residual_(problem.create_vector()) {
  const double t0 = MPI_Wtime();
  const ConstraintSet::Point kept = constraints.point();
  VecHandle u(problem.create_vector()), z(problem.create_vector());
  MatHandle J(problem.create_matrix());
  // The tangent's LU factors, with options of its own: none of the run's solver objects
  // factors this matrix, and a transposed solve needs a factorization that supports one.
  KspHandle ksp;
  HS_PETSC(KSPCreate(problem.comm(), ksp.out()));
  HS_PETSC(KSPSetType(ksp, KSPPREONLY));
  PC pc = nullptr;
  HS_PETSC(KSPGetPC(ksp, &pc));
  HS_PETSC(PCSetType(pc, PCLU));
  HS_PETSC(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
  ConstraintLinearization lin;
  std::vector<double> controls;
  const Eigen::MatrixXd& actuations = system.training_actuations();
  const Eigen::MatrixXd& states = system.training_states();
  for (Eigen::Index s = 0; s < states.rows(); ++s) {
    for (size_t a = 0; a < actuators.size(); ++a)
      constraints[actuators[a]].prescribe(Constraint::Control::multiplier,
                                          actuations(s, static_cast<Eigen::Index>(a)));
    system.place(states.row(s).transpose(), u, true);
    problem.exact_next_tangent();  // J at the sample, not Newton's from the last one
    if (!constraints.residual(u, 1.0, residual_, controls) ||
        !constraints.linearize(u, 1.0, J, lin))
      throw SolveError("reduced model: the full tangent at training sample " +
                       std::to_string(s + 1) + " cannot be evaluated (the error indicator)");
    HS_PETSC(KSPSetOperators(ksp, J, J));
    Eigen::MatrixXd influence(system.dofs(), static_cast<Eigen::Index>(rows.size()));
    for (size_t r = 0; r < rows.size(); ++r) {
      HS_PETSC(KSPSolveTranspose(ksp, rows[r], z));
      KSPConvergedReason reason;
      HS_PETSC(KSPGetConvergedReason(ksp, &reason));
      if (reason < 0)
        throw SolveError("reduced model: the full tangent at training sample " +
                         std::to_string(s + 1) + " cannot be factored (the error indicator)");
      influence.col(static_cast<Eigen::Index>(r)) = local_values(z);
    }
    influence_.push_back(std::move(influence));
  }
  constraints.return_to(kept);
  setup_s_ = MPI_Wtime() - t0;
}

bool ResidualErrorIndicator::estimate(Vec u, const Eigen::VectorXd& lambda, Eigen::VectorXd& dx) {
  const ConstraintSet::Point kept = constraints_.point();
  std::vector<double> controls;
  const bool ok = constraints_.residual(u, 1.0, residual_, controls);
  constraints_.return_to(kept);
  if (!ok) return false;
  dx = -influence_[system_.nearest_training_sample(lambda)].transpose() * local_values(residual_);
  return true;
}

double ResidualErrorIndicator::largest_move(const Eigen::VectorXd& dx) {
  double largest = 0;
  for (Eigen::Index i = 0; i + 2 < dx.size(); i += 3)
    largest = std::max(largest, dx.segment<3>(i).norm());
  return largest;
}

}  // namespace hs
