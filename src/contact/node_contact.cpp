#include "contact/node_contact.hpp"

#include "contact/barrier.hpp"

namespace hs {

NodeContact node_contact(const std::vector<ObstacleShape>& obstacles, const Eigen::Vector3d& x,
                         double s, double area, const ContactBarrier& barrier, bool project) {
  NodeContact out;
  out.force.assign(obstacles.size(), Eigen::Vector3d::Zero());
  out.stiffness.assign(obstacles.size(), Eigen::Matrix3d::Zero());
  out.active.assign(obstacles.size(), 0);
  const double scale = barrier.stiffness * area;
  for (size_t o = 0; o < obstacles.size(); ++o) {
    const SignedDistance sd = signed_distance(obstacles[o], x, s);
    if (sd.d >= barrier.distance) continue;
    if (!(sd.d > 0)) {
      out.valid = false;
      if (out.inside < 0) out.inside = static_cast<int>(o);
      continue;
    }
    const BarrierValue b = contact_barrier(sd.d, barrier.distance);
    out.energy += scale * b.value;
    out.force[o] = scale * b.slope * sd.gradient;
    out.active[o] = 1;
    out.gradient += out.force[o];
    out.stiffness[o] =
        scale * (b.curvature * sd.gradient * sd.gradient.transpose() + b.slope * sd.hessian);
    out.hessian += out.stiffness[o];
  }
  if (project && !out.hessian.isZero(0)) {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(out.hessian);
    const Eigen::Vector3d clamped = eig.eigenvalues().cwiseMax(0.0);
    out.hessian = eig.eigenvectors() * clamped.asDiagonal() * eig.eigenvectors().transpose();
  }
  return out;
}

}  // namespace hs
