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
// and the barrier's by the chain rule in d^2.
//
// Two edges a0 a1 and b0 b1 that cross without a node near the other's triangles (sharp edges
// pressed across each other) are kept apart by a pair of their own:
//   E = kappa w m(c) b(d),   d^2 = ((b0 - a0) . n)^2 / |n|^2,  n = (a1 - a0) x (b1 - b0),
// where the nearest points lie inside both edges, else a vertex's distance to the other edge's
// line or to its nearest vertex, as the segments' closest points fall; w is the mean of the two
// edges' shares of the area (a third of each triangle beside them). As the edges turn parallel
// the line-line distance loses its direction and the nearest points jump along the edges, so
// the pair fades out, m(c) the quintic smoothstep from c = eps/2 (0) to eps (1) of c = |n|^2,
// eps = 1e-3 |a|^2 |b|^2 at rest (within 1.3 degrees of parallel there is no pair; such edges
// are held by the node-triangle pairs). Incremental potential contact's mollifier, (2 - c/eps)
// c/eps, reaches c = 0; there the kind of the nearest points flipped under perturbations of
// 1e-6 of an edge (two surfaces meshed alike from a corner), and the tangent no longer matched
// the residual. Pure.
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

// The features of edges x[0] x[1] and x[2] x[3] nearest each other: `count` of the 4 vertices
// as the distance takes them, indices 0-3 in `vertex`: 4 the two lines, 3 a vertex and the
// other edge's line (the vertex first), 2 a vertex of each.
struct EdgeFeature {
  int count = 4;
  int vertex[4] = {0, 1, 2, 3};
};
EdgeFeature nearest_edge_feature(const Eigen::Vector3d* x);
double edge_squared_distance(const Eigen::Vector3d* x, const EdgeFeature& f);
// The weights w of the features' nearest points: sum_k w_k x_k is the point of edge a less
// the point of edge b (w_0 + w_1 = 1, w_2 + w_3 = -1).
void edge_feature_weights(const Eigen::Vector3d* x, const EdgeFeature& f, double* w);

// kappa w m(c) b(d) of the two edges x[0 .. 3] and its derivatives over their 12 coordinates;
// `parallel`: eps. Projected with `project`, as pair_barrier. d > 0 is assumed.
PairTerm edge_pair_barrier(const Eigen::Vector3d* x, const EdgeFeature& f, double weight,
                           double parallel, const ContactBarrier& barrier, bool project);

}  // namespace hs
