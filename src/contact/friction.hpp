// Coulomb friction of a node on the rigid obstacles, lagged as in incremental potential
// contact (docs/contact.md, "Friction"): over a load or time step, each obstacle o the node
// touched at the step's start pushes on it with a normal force of size lambda_o across the
// plane normal to n_o, both frozen at that start. The node's slip on the obstacle since then,
//   w = P_o ((x - x0) - (s - s0) move_o),   P_o = I - n_o n_o^T,
// costs the potential mu_o lambda_o f0(|w|), where f0(y) = y beyond the slip eps_v at which
// the node slides and f0(y) = -y^3 / (3 eps_v^2) + y^2 / eps_v + eps_v / 3 below it (sticking:
// a spring whose force reaches mu lambda at eps_v, C1 where it meets the sliding branch). Its
// gradient is the friction force (of size mu lambda while sliding, against the slip), its
// Hessian semi-definite. Pure.
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "contact/node_contact.hpp"
#include "contact/obstacle.hpp"

namespace hs {

// What the step's start froze for one node: where it was, at which load factor, and per
// obstacle the normal force's size (0 where it did not touch) and direction.
struct FrictionLag {
  Eigen::Vector3d x0 = Eigen::Vector3d::Zero();
  double s0 = 0;
  std::vector<double> normal_force;
  std::vector<Eigen::Vector3d> normal;
};

// The lag at a node at x0, load factor s0: the barrier's force of each obstacle there.
FrictionLag friction_lag(const std::vector<ObstacleShape>& obstacles, const Eigen::Vector3d& x0,
                         double s0, double area, const ContactBarrier& barrier);

// Adds the friction's energy, gradient and Hessian at x, load factor s, to `out` (and each
// obstacle's friction force to out.force), with slip eps_v.
void add_friction(const std::vector<ObstacleShape>& obstacles, const FrictionLag& lag,
                  const Eigen::Vector3d& x, double s, double eps_v, NodeContact& out);

}  // namespace hs
