#include "contact/friction.hpp"

#include "contact/barrier.hpp"

namespace hs {

FrictionLag friction_lag(const std::vector<ObstacleShape>& obstacles, const Eigen::Vector3d& x0,
                         double s0, double area, const ContactBarrier& barrier) {
  FrictionLag lag;
  lag.x0 = x0;
  lag.s0 = s0;
  lag.normal_force.assign(obstacles.size(), 0.0);
  lag.normal.assign(obstacles.size(), Eigen::Vector3d::Zero());
  for (size_t o = 0; o < obstacles.size(); ++o) {
    if (obstacles[o].friction == 0) continue;
    const SignedDistance sd = signed_distance(obstacles[o], x0, s0);
    if (!(sd.d > 0) || sd.d >= barrier.distance) continue;
    lag.normal_force[o] = -barrier.stiffness * area * contact_barrier(sd.d, barrier.distance).slope;
    lag.normal[o] = sd.gradient;
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
    const Eigen::Vector3d move(obstacles[o].move[0], obstacles[o].move[1], obstacles[o].move[2]);
    const Eigen::Vector3d w = P * ((x - lag.x0) - (s - lag.s0) * move);
    const double y = w.norm();
    // f0, f1 = f0' and the Hessian's two parts: f1(y)/y P and g(y) w w^T.
    double f0 = 0, f1_over_y = 0, g = 0;
    if (y >= eps_v) {
      f0 = y;
      f1_over_y = 1 / y;
      g = -1 / (y * y * y);
    } else {
      f0 = -y * y * y / (3 * eps_v * eps_v) + y * y / eps_v + eps_v / 3;
      f1_over_y = -y / (eps_v * eps_v) + 2 / eps_v;
      g = y > 0 ? -1 / (eps_v * eps_v * y) : 0;
    }
    const Eigen::Vector3d force = scale * f1_over_y * w;
    out.energy += scale * f0;
    out.gradient += force;
    out.force[o] += force;
    out.hessian += scale * (f1_over_y * P + g * w * w.transpose());
  }
}

}  // namespace hs
