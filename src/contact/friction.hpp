// Coulomb friction of a node on the rigid obstacles (docs/contact.md, "Friction"), regularised
// as in incremental potential contact and anchored so that a sticking node does not creep.
// Over a load or time step, each obstacle o the node touched at the step's start pushes on it
// with a normal force of size lambda_o across the plane normal to n_o, both frozen (lagged) at
// that start, and holds it by a tangential anchor a_o carried with the obstacle. The node's
// slip from its anchor,
//   w = P_o ((x - s move_o) - a_o),   P_o = I - n_o n_o^T,
// costs the potential mu_o lambda_o f0(|w|), where f0(y) = y beyond the slip eps_v at which
// the node slides and f0(y) = -y^3 / (3 eps_v^2) + y^2 / eps_v + eps_v / 3 below it (a spring
// whose force reaches mu lambda at eps_v, C1 where it meets the sliding branch). Its gradient
// is the friction force, of size mu lambda f0'(|w|) against the slip; its Hessian is
// semi-definite. At each step's end a sliding node's anchor follows it to eps_v behind
// (the force stays mu lambda), a sticking node's stays. Pure.
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "contact/node_contact.hpp"
#include "contact/obstacle.hpp"

namespace hs {

// What a step's start froze for one node, per obstacle: the normal force's size (0 where it
// did not touch), its direction, and the anchor (in the obstacle's frame: less s * move).
struct FrictionLag {
  std::vector<double> normal_force;
  std::vector<Eigen::Vector3d> normal, anchor;
};

// f0(y) of the slip y >= 0 with slip eps_v, f0'(y) / y and g(y) = (f0''(y) - f0'(y) / y) / y^2:
// the potential's Hessian in the slip w is f0'/y P + g w w^T (P the projector normal to the
// lagged normal). Shared with the surfaces' own friction (pair_friction.hpp).
struct SlipPotential {
  double value = 0, slope_over_y = 0, g = 0;
};
SlipPotential slip_potential(double y, double eps_v);

// The lag of a node at x0, load factor s0, that had `previous` over the step before (empty:
// none, the first step): each touching obstacle's barrier force there, and the anchors.
FrictionLag friction_lag(const std::vector<ObstacleShape>& obstacles, const Eigen::Vector3d& x0,
                         double s0, double area, const ContactBarrier& barrier, double eps_v,
                         const FrictionLag& previous);

// Adds the friction's energy, gradient and Hessian at x, load factor s, to `out` (and each
// obstacle's friction force and its derivative to out.force and out.stiffness), with slip
// eps_v.
void add_friction(const std::vector<ObstacleShape>& obstacles, const FrictionLag& lag,
                  const Eigen::Vector3d& x, double s, double eps_v, NodeContact& out);

}  // namespace hs
