// Proper orthogonal decomposition of displacement snapshots (docs/reduced_models.md): the
// reduced basis of a reduced-order model. The snapshots' thin SVD S = U Sigma V^T; the basis is
// the first k columns of U, k the smallest count whose discarded energy
//   sum_{i > k} sigma_i^2 / sum_i sigma_i^2
// is at most the energy tolerance (and k <= max_modes). Pure: Eigen only.
#pragma once

#include <Eigen/Dense>

namespace hs {

struct PodBasis {
  Eigen::MatrixXd modes;            // n x k, orthonormal columns
  Eigen::VectorXd singular_values;  // all of them, largest first
  double discarded_energy = 0;      // the fraction left out by the k kept modes
};

// snapshots: n x s, one snapshot per column. Throws std::invalid_argument for an empty
// matrix, a non-finite entry, an energy tolerance outside [0, 1) or max_modes < 1.
PodBasis pod_basis(const Eigen::MatrixXd& snapshots, double energy_tolerance, int max_modes);

}  // namespace hs
