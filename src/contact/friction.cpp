#include "contact/friction.hpp"

#include "contact/barrier.hpp"

namespace hs {
namespace {

Eigen::Vector3d moved(const ObstacleShape& o, const Eigen::Vector3d& x, double s) {
  return x - s * Eigen::Vector3d(o.move[0], o.move[1], o.move[2]);
}

}  // namespace

SlipPotential slip_potential(double y, double eps_v) {
  if (y >= eps_v) return {y, 1 / y, -1 / (y * y * y)};
  return {-y * y * y / (3 * eps_v * eps_v) + y * y / eps_v + eps_v / 3,
          -y / (eps_v * eps_v) + 2 / eps_v, y > 0 ? -1 / (eps_v * eps_v * y) : 0};
}

FrictionLag friction_lag(const std::vector<ObstacleShape>& obstacles, const Eigen::Vector3d& x0,
                         double s0, double area, const ContactBarrier& barrier, double eps_v,
                         const FrictionLag& previous) {
  FrictionLag lag;
  lag.normal_force.assign(obstacles.size(), 0.0);
  lag.normal.assign(obstacles.size(), Eigen::Vector3d::Zero());
  lag.anchor.assign(obstacles.size(), Eigen::Vector3d::Zero());
  for (size_t o = 0; o < obstacles.size(); ++o) {
    if (obstacles[o].friction == 0) continue;
    const SignedDistance sd = signed_distance(obstacles[o], x0, s0);
    if (!(sd.d > 0) || sd.d >= barrier.distance) continue;
    lag.normal_force[o] = -barrier.stiffness * area * contact_barrier(sd.d, barrier.distance).slope;
    lag.normal[o] = sd.gradient;
    const Eigen::Vector3d here = moved(obstacles[o], x0, s0);
    lag.anchor[o] = here;  // a new contact holds the node where it touched
    if (previous.normal_force.empty() || previous.normal_force[o] == 0) continue;
    const Eigen::Matrix3d P =
        Eigen::Matrix3d::Identity() - previous.normal[o] * previous.normal[o].transpose();
    const Eigen::Vector3d w = P * (here - previous.anchor[o]);
    const double y = w.norm();
    lag.anchor[o] = y > eps_v ? Eigen::Vector3d(here - eps_v / y * w) : Eigen::Vector3d(here - w);
  }
  return lag;
}

void add_friction(const std::vector<ObstacleShape>& obstacles, const FrictionLag& lag,
                  const Eigen::Vector3d& x, double s, double eps_v, NodeContact& out) {
  for (size_t o = 0; o < obstacles.size(); ++o) {
    const double scale = obstacles[o].friction * lag.normal_force[o];
    if (scale == 0) continue;
    const Eigen::Vector3d n = lag.normal[o];
    const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - n * n.transpose();
    const Eigen::Vector3d w = P * (moved(obstacles[o], x, s) - lag.anchor[o]);
    const SlipPotential f = slip_potential(w.norm(), eps_v);
    const Eigen::Vector3d force = scale * f.slope_over_y * w;
    out.energy += scale * f.value;
    out.gradient += force;
    out.force[o] += force;
    const Eigen::Matrix3d stiffness = scale * (f.slope_over_y * P + f.g * w * w.transpose());
    out.stiffness[o] += stiffness;
    out.hessian += stiffness;
  }
}

}  // namespace hs
