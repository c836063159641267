// Self-contact between a node of the body's surface and a triangle of it (docs/contact.md,
// "Self-contact"), as incremental potential contact sets it: the distance from the node p to
// the triangle is its distance to the triangle's feature nearest to p (its plane, the line of
// one of its edges, or a vertex), and the pair stores
//   E = kappa A_p b(d),   d^2 = ((p - t0) . n)^2 / |n|^2       (face, n = (t1 - t0) x (t2 - t0)),
//                         d^2 = |(q0 - p) x (q1 - p)|^2 / |q1 - q0|^2   (edge q0 q1),
//                         d^2 = |p - q|^2                        (vertex q),
// b the barrier of barrier.hpp and A_p the node's share of the surfaces' area, as a node
// against an obstacle does. Each feature's d^2 is a smooth function of its 2 to 4 nodes; its
// gradient and Hessian come from automatic differentiation (Eigen's forward mode, nested),
// and the barrier's by the chain rule in d^2. Pure.
#pragma once

#include <Eigen/Dense>

#include "contact/node_contact.hpp"

namespace hs {

// The feature of triangle (t0, t1, t2) nearest to p: `count` vertices of it (1 a vertex, 2 an
// edge, 3 the face), their indices 0-2 in `vertex`.
struct TriangleFeature {
  int count = 3;
  int vertex[3] = {0, 1, 2};
};
TriangleFeature nearest_feature(const Eigen::Vector3d& p, const Eigen::Vector3d& t0,
                                const Eigen::Vector3d& t1, const Eigen::Vector3d& t2);

// d^2 from x[0] (the node) to the feature of nodes x[1 .. n-1] (n = 2, 3 or 4), as above.
double feature_squared_distance(const Eigen::Vector3d* x, int n);

using PairVector = Eigen::Matrix<double, 12, 1>;
using PairMatrix = Eigen::Matrix<double, 12, 12>;

// kappa A b(d) of the pair and its derivatives with respect to the 3 n coordinates of x[0 ..
// n-1] (the first 3 n entries; the rest zero). With `project`, the Hessian projected onto
// the semi-definite matrices (for CG, as node_contact does). d > 0 is assumed.
struct PairTerm {
  double distance = 0, energy = 0;
  PairVector gradient = PairVector::Zero();
  PairMatrix hessian = PairMatrix::Zero();
};
PairTerm pair_barrier(const Eigen::Vector3d* x, int n, double area, const ContactBarrier& barrier,
                      bool project);

}  // namespace hs
