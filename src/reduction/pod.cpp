#include "reduction/pod.hpp"

#include <algorithm>
#include <stdexcept>

namespace hs {

PodBasis pod_basis(const Eigen::MatrixXd& snapshots, double energy_tolerance, int max_modes) {
  if (snapshots.size() == 0) throw std::invalid_argument("pod_basis: no snapshots");
  if (!snapshots.allFinite()) throw std::invalid_argument("pod_basis: a snapshot is not finite");
  if (!(energy_tolerance >= 0 && energy_tolerance < 1))
    throw std::invalid_argument("pod_basis: the energy tolerance must lie in [0, 1)");
  if (max_modes < 1) throw std::invalid_argument("pod_basis: max_modes must be at least 1");
  // Bidiagonal divide and conquer: accurate in the small singular values that decide k.
  Eigen::BDCSVD<Eigen::MatrixXd> svd(snapshots, Eigen::ComputeThinU);
  PodBasis pod;
  pod.singular_values = svd.singularValues();
  const Eigen::VectorXd energy = pod.singular_values.array().square();
  const double total = energy.sum();
  const int available = static_cast<int>(energy.size());
  int k = 0;
  double kept = 0;
  if (total > 0) {
    while (k < std::min(available, max_modes) && (total - kept) > energy_tolerance * total)
      kept += energy(k++);
  }
  k = std::max(k, 1);
  if (total > 0 && kept == 0) kept = energy(0);
  pod.discarded_energy = total > 0 ? std::max(0.0, (total - kept) / total) : 0.0;
  pod.modes = svd.matrixU().leftCols(k);
  return pod;
}

}  // namespace hs
