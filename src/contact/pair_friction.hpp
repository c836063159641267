// Coulomb friction between a node of the body's surfaces and a triangle of them (docs/contact.md,
// "Friction between the surfaces"), lagged over each load or time step as friction on an
// obstacle is (friction.hpp). At a step's start each pair within dhat freezes the point q of
// its feature nearest to the node p as weights of the feature's nodes, q = sum_k beta_k x_k,
// the normal n = (p - q) / |p - q| and the size lambda of the barrier's force on p. Over the
// step the pair's relative position r = x_p - sum_k beta_k x_k slips from an anchor a by
//   w = P (r - a),   P = I - n n^T,
// and costs mu lambda f0(|w|), f0 of friction.hpp. r is linear in the pair's nodes with the
// weights c = (1, -beta_1, ...): the gradient at node i is c_i times the friction force on p,
// the Hessian's block (i, j) is c_i c_j times its 3x3 stiffness (semi-definite), and the forces
// on the pair's nodes add up to zero. Pure.
#pragma once

#include <Eigen/Dense>
#include <cstdint>

#include "contact/surface_pair.hpp"

namespace hs {

// One pair's lag. node[0] and face name the pair from one step to the next.
struct PairFrictionLag {
  int count = 0;                    // the node, then its feature's 1 to 3 nodes (or 2 edges' 4)
  int32_t node[4] = {0, 0, 0, 0};   // surface node numbers (the caller's)
  int32_t face = -1;                // the triangle (the caller's number)
  double weight[4] = {1, 0, 0, 0};  // c
  double normal_force = 0;          // lambda (N)
  double friction = 0;              // mu
  Eigen::Vector3d normal = Eigen::Vector3d::Zero(), anchor = Eigen::Vector3d::Zero();
};

// The weights beta of the point nearest to x[0] on the plane (n = 4), the line (n = 3) or the
// vertex (n = 2) of the feature x[1 .. n-1], into beta[0 .. n-2].
void feature_weights(const Eigen::Vector3d* x, int n, double* beta);

// The lag of the pair of `nodes` (count of them: the node, then its feature's) at positions x,
// with friction mu, whose barrier pushes the node with normal_force. `carried`: the slip w the pair
// had reached under the step before (pair_slip of its lag there, zero for a new pair); the anchor
// is set so that the new step starts from it, turned into the new tangent plane at its length, or
// at eps_v where the pair slid farther.
PairFrictionLag pair_friction_lag(const int32_t* nodes, const Eigen::Vector3d* x, int count,
                                  int32_t face, double mu, double normal_force,
                                  const Eigen::Vector3d& carried, double eps_v);

// The same for a pair of edges (nodes: the one edge's two, then the other's; x their positions)
// whose nearest features are f: r is the one edge's nearest point less the other's
// (edge_feature_weights), and `face` the caller's name of the pair.
PairFrictionLag edge_friction_lag(const int32_t* nodes, const Eigen::Vector3d* x,
                                  const EdgeFeature& f, int32_t face, double mu,
                                  double normal_force, const Eigen::Vector3d& carried,
                                  double eps_v);

// The slip w of a lagged pair whose nodes are at x.
Eigen::Vector3d pair_slip(const PairFrictionLag& lag, const Eigen::Vector3d* x);

// mu lambda f0(|w|), mu the lag's, with its gradient and Hessian over the pair's nodes at x
// (term.distance is 0: a friction term holds no gap).
PairTerm pair_friction(const PairFrictionLag& lag, const Eigen::Vector3d* x, double eps_v);

}  // namespace hs
