// One node's contact with the rigid obstacles (docs/contact.md): the barrier energy
//   E(x) = kappa A sum_o b(d_o(x)),   b of barrier.hpp, d_o the signed distance of obstacle o,
// its gradient (the node's contact force on the obstacles, a residual term) and Hessian
//   d2E/dx2 = kappa A sum_o (b'' n n^T + b' H_o),
// optionally projected onto the positive semi-definite matrices, as incremental potential
// contact projects each contact's Hessian: b' < 0, so a curved obstacle's b' H is negative
// across it and can make the tangent indefinite, which CG cannot take. Pure.
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "contact/obstacle.hpp"

namespace hs {

struct ContactBarrier {
  double distance = 0;   // dhat (m)
  double stiffness = 0;  // kappa (Pa/m)
};

struct NodeContact {
  bool valid = true;  // false: the node is on or inside an obstacle (d <= 0)
  int inside = -1;    // then: the first such obstacle
  double energy = 0;
  Eigen::Vector3d gradient = Eigen::Vector3d::Zero();  // dE/dx, per obstacle summed
  Eigen::Matrix3d hessian = Eigen::Matrix3d::Zero();
  // Per obstacle: dE/dx (the force the node exerts on it), its exact derivative d(dE/dx)/dx
  // (never projected: the linearisation of a contact-force effector) and whether d < dhat.
  std::vector<Eigen::Vector3d> force;
  std::vector<Eigen::Matrix3d> stiffness;
  std::vector<char> active;
};

// Node at x (current position) of reference area `area`, obstacles at load factor s. With
// `project`, the Hessian is the projected one; without it, the exact one (for tests).
NodeContact node_contact(const std::vector<ObstacleShape>& obstacles, const Eigen::Vector3d& x,
                         double s, double area, const ContactBarrier& barrier, bool project);

}  // namespace hs
