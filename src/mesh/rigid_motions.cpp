#include "mesh/rigid_motions.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "common/error.hpp"

namespace hs {
namespace {

// A free mode in words: a translation when its rotation part vanishes, else a rotation
// about the direction of its rotation part (through some point: a screw motion is a rotation
// plus a translation along its axis, which the translation part gives).
std::string describe(const Eigen::Matrix<double, 6, 1>& v) {
  const Eigen::Vector3d t = v.head<3>(), w = v.tail<3>();
  const bool rotation = w.norm() > 1e-6 * v.norm();
  Eigen::Vector3d d = rotation ? w.normalized() : t.normalized();
  // Point the direction to positive along its largest component, so that an axis reads "z".
  int k = 0;
  d.cwiseAbs().maxCoeff(&k);
  if (d[k] < 0) d = -d;
  std::string axis;
  if (d[k] > 1 - 1e-9) {
    axis = std::string(1, "xyz"[k]);
  } else {
    char buffer[96];
    std::snprintf(buffer, sizeof buffer, "an axis along (%.2g, %.2g, %.2g)", d[0] + 0.0, d[1] + 0.0,
                  d[2] + 0.0);
    axis = buffer;
  }
  return rotation ? "rotation about " + axis : "translation along " + axis;
}

}  // namespace

template <class Index>
std::vector<std::string> free_rigid_motions(const std::vector<DirichletConfig>& conditions,
                                            const std::map<std::string, std::vector<Index>>& groups,
                                            const std::vector<double>& x, MPI_Comm comm) {
  // Centre and size of the body, so that rotations and translations weigh alike.
  const double inf = std::numeric_limits<double>::infinity();
  double box[6] = {inf, inf, inf, inf, inf, inf};  // min x, y, z; -max x, y, z
  for (size_t n = 0; n < x.size() / 3; ++n)
    for (int d = 0; d < 3; ++d) {
      box[d] = std::min(box[d], x[3 * n + d]);
      box[3 + d] = std::min(box[3 + d], -x[3 * n + d]);
    }
  MPI_Allreduce(MPI_IN_PLACE, box, 6, MPI_DOUBLE, MPI_MIN, comm);
  double c[3], size = 0;
  for (int d = 0; d < 3; ++d) {
    c[d] = 0.5 * (box[d] - box[3 + d]);
    size = std::max(size, -box[3 + d] - box[d]);
  }
  if (!(size > 0)) size = 1;

  Eigen::Matrix<double, 6, 6> G = Eigen::Matrix<double, 6, 6>::Zero();
  for (const DirichletConfig& bc : conditions) {
    const auto it = groups.find(bc.group);
    if (it == groups.end()) continue;
    for (const Index n : it->second) {
      const double p[3] = {(x[3 * n] - c[0]) / size, (x[3 * n + 1] - c[1]) / size,
                           (x[3 * n + 2] - c[2]) / size};
      for (int d = 0; d < 3; ++d) {
        if (!bc.components[d]) continue;
        // Component d of the translations e_j and of the rotations e_j x p.
        Eigen::Matrix<double, 6, 1> r = Eigen::Matrix<double, 6, 1>::Zero();
        r[d] = 1;
        const int a = (d + 1) % 3, b = (d + 2) % 3;  // (e_j x p)_d = eps_{d j k} p_k
        r[3 + a] = p[b];
        r[3 + b] = -p[a];
        G += r * r.transpose();
      }
    }
  }
  MPI_Allreduce(MPI_IN_PLACE, G.data(), 36, MPI_DOUBLE, MPI_SUM, comm);
  std::vector<std::string> free;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eigen(G);
  const double largest = eigen.eigenvalues().maxCoeff();
  for (int k = 0; k < 6; ++k)
    if (!(eigen.eigenvalues()[k] > 1e-10 * largest))
      free.push_back(describe(eigen.eigenvectors().col(k)));
  return free;
}

template <class Index>
void check_rigid_motions_held(const Config& config,
                              const std::map<std::string, std::vector<Index>>& groups,
                              const std::vector<double>& x, MPI_Comm comm) {
  // Obstacles may hold the body (a block resting on a floor): their barrier acts from the
  // first residual where the body starts within contact.distance of them (docs/contact.md).
  if (config.time.type == TimeType::dynamic || !config.obstacles.empty()) return;
  if (config.dirichlet.empty())
    throw InputError(config.deck_path +
                     ": boundary: nothing holds the body (no Dirichlet condition): a static run "
                     "needs one to remove the rigid motions, e.g. boundary: [{group: clamped}]");
  const auto free = free_rigid_motions(config.dirichlet, groups, x, comm);
  if (free.empty()) return;
  std::string list;
  for (const auto& f : free) list += (list.empty() ? "" : ", ") + f;
  throw InputError(config.deck_path + ": boundary: the conditions leave the body free to move (" +
                   list +
                   "): a static run needs them to hold every rigid motion; constrain "
                   "more components or another group");
}

template std::vector<std::string> free_rigid_motions(
    const std::vector<DirichletConfig>&, const std::map<std::string, std::vector<int32_t>>&,
    const std::vector<double>&, MPI_Comm);
template std::vector<std::string> free_rigid_motions(
    const std::vector<DirichletConfig>&, const std::map<std::string, std::vector<int64_t>>&,
    const std::vector<double>&, MPI_Comm);
template void check_rigid_motions_held(const Config&,
                                       const std::map<std::string, std::vector<int32_t>>&,
                                       const std::vector<double>&, MPI_Comm);
template void check_rigid_motions_held(const Config&,
                                       const std::map<std::string, std::vector<int64_t>>&,
                                       const std::vector<double>&, MPI_Comm);

}  // namespace hs
