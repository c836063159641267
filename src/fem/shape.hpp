// P1/P2 Lagrange shape functions on the reference tetrahedron and triangle, in gmsh node order
// (src/mesh/mesh.hpp). With barycentric coordinates L (L_0 = 1 - sum xi, L_d+1 = xi_d):
//   P1: N_a = L_a
//   P2: vertex a: N_a = L_a (2 L_a - 1),  edge node on (a, b): N = 4 L_a L_b
//   Tet10 edges 4:(0,1) 5:(1,2) 6:(2,0) 7:(3,0) 8:(3,2) 9:(3,1);  Tri6 edges 3:(0,1) 4:(1,2)
//   5:(2,0)
#pragma once

#include <Eigen/Dense>

namespace hs {

// Nodes per element of the given order (1 or 2; else hs::InputError).
int tet_num_nodes(int order);
int tri_num_nodes(int order);

// Values N[a] and reference gradients dN[3a + d] = dN_a/dxi_d at xi (either may be nullptr).
void tet_shape(int order, const Eigen::Vector3d& xi, double* N, double* dN);
// Values N[a] and reference gradients dN[2a + d] = dN_a/dxi_d at xi (either may be nullptr).
void tri_shape(int order, const Eigen::Vector2d& xi, double* N, double* dN);

// Reference coordinates of node a.
Eigen::Vector3d tet_node(int order, int a);
Eigen::Vector2d tri_node(int order, int a);

}  // namespace hs
