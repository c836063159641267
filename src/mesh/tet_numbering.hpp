// A tetrahedron's node numbering as the mesh routines share it (gmsh's order, mesh.hpp): the
// edge nodes of P2, the outward faces, and the parity test of a face's vertex order.
#pragma once

#include <Eigen/Dense>
#include <cstdint>

#include "mesh/mesh.hpp"

namespace hs::tet {

// Tet10 edge node of each pair of vertices; -1 on the diagonal.
inline constexpr int kEdgeNode[4][4] = {{-1, 4, 6, 7}, {4, -1, 5, 9}, {6, 5, -1, 8}, {7, 9, 8, -1}};

// For a positively oriented tetrahedron, the face opposite vertex v listed so that its
// right-hand normal points away from v: e.g. face (0, 2, 1) has normal
// (x2 - x0) x (x1 - x0), whose dot product with x3 - x0 is -det < 0.
inline constexpr int kOutwardFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

// Whether (p, q, r) is an odd permutation of its sorted order.
inline bool odd_order(int64_t p, int64_t q, int64_t r) {
  return ((p > q) + (p > r) + (q > r)) % 2 == 1;
}

inline Eigen::Vector3d node_x(const Mesh& mesh, int64_t n) {
  return Eigen::Vector3d(mesh.x[3 * n], mesh.x[3 * n + 1], mesh.x[3 * n + 2]);
}

}  // namespace hs::tet
