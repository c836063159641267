#include "fem/shape.hpp"

#include <string>

#include "common/error.hpp"

namespace hs {
namespace {

// Vertex pairs of the edge nodes, in gmsh order.
constexpr int kTetEdges[6][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 0}, {3, 2}, {3, 1}};
constexpr int kTriEdges[3][2] = {{0, 1}, {1, 2}, {2, 0}};

void check_order(int order) {
  if (order != 1 && order != 2)
    throw InputError("element order " + std::to_string(order) + " is not supported (1 or 2)");
}

// Lagrange P1/P2 on a simplex of dimension D from its D + 1 barycentric coordinates, whose
// gradients in xi are dL[v] (L_0 = 1 - sum xi, L_v = xi_{v-1}).
template <int D, int E>
void simplex_shape(int order, const double* xi, const int (&edges)[E][2], double* N, double* dN) {
  double L[D + 1], dL[D + 1][D];
  L[0] = 1.0;
  for (int d = 0; d < D; ++d) {
    L[0] -= xi[d];
    L[d + 1] = xi[d];
    for (int e = 0; e < D; ++e) {
      dL[0][e] = -1.0;
      dL[d + 1][e] = (d == e) ? 1.0 : 0.0;
    }
  }
  for (int a = 0; a <= D; ++a) {
    if (N) N[a] = (order == 1) ? L[a] : L[a] * (2.0 * L[a] - 1.0);
    if (dN)
      for (int d = 0; d < D; ++d)
        dN[D * a + d] = (order == 1) ? dL[a][d] : (4.0 * L[a] - 1.0) * dL[a][d];
  }
  if (order == 1) return;
  for (int e = 0; e < E; ++e) {
    const int a = edges[e][0], b = edges[e][1], node = D + 1 + e;
    if (N) N[node] = 4.0 * L[a] * L[b];
    if (dN)
      for (int d = 0; d < D; ++d) dN[D * node + d] = 4.0 * (dL[a][d] * L[b] + L[a] * dL[b][d]);
  }
}

}  // namespace

int tet_num_nodes(int order) {
  check_order(order);
  return order == 1 ? 4 : 10;
}

int tri_num_nodes(int order) {
  check_order(order);
  return order == 1 ? 3 : 6;
}

void tet_shape(int order, const Eigen::Vector3d& xi, double* N, double* dN) {
  check_order(order);
  simplex_shape<3>(order, xi.data(), kTetEdges, N, dN);
}

void tri_shape(int order, const Eigen::Vector2d& xi, double* N, double* dN) {
  check_order(order);
  simplex_shape<2>(order, xi.data(), kTriEdges, N, dN);
}

Eigen::Vector3d tet_node(int order, int a) {
  const Eigen::Vector3d vertices[4] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  if (a < 0 || a >= tet_num_nodes(order))
    throw InputError("tetrahedron node " + std::to_string(a) + " does not exist");
  if (a < 4) return vertices[a];
  return 0.5 * (vertices[kTetEdges[a - 4][0]] + vertices[kTetEdges[a - 4][1]]);
}

Eigen::Vector2d tri_node(int order, int a) {
  const Eigen::Vector2d vertices[3] = {{0, 0}, {1, 0}, {0, 1}};
  if (a < 0 || a >= tri_num_nodes(order))
    throw InputError("triangle node " + std::to_string(a) + " does not exist");
  if (a < 3) return vertices[a];
  return 0.5 * (vertices[kTriEdges[a - 3][0]] + vertices[kTriEdges[a - 3][1]]);
}

}  // namespace hs
