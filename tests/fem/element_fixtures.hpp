// Test elements: distorted (and, for P2, curved) tetrahedra, their outward faces, and a
// small conforming mesh of a cube. Shared by the tests of tests/fem.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <map>
#include <random>
#include <utility>
#include <vector>

namespace hs::testing_fixtures {

// gmsh Tet10 edge nodes: node 4 + e sits on the vertex pair kTetEdges[e].
constexpr int kTetEdges[6][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 0}, {3, 2}, {3, 1}};

inline int tet_edge_node(int a, int b) {
  for (int e = 0; e < 6; ++e)
    if ((kTetEdges[e][0] == a && kTetEdges[e][1] == b) ||
        (kTetEdges[e][0] == b && kTetEdges[e][1] == a))
      return 4 + e;
  return -1;
}

// Faces of a positively oriented tetrahedron, ordered so that the right-hand normal points out.
constexpr int kOutwardFaces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};

// Local node indices of face f as a Tri3 (order 1) or Tri6 (order 2) in gmsh order.
inline std::vector<int> face_nodes(int order, int f) {
  const int* v = kOutwardFaces[f];
  std::vector<int> nodes = {v[0], v[1], v[2]};
  if (order == 2)
    for (int e = 0; e < 3; ++e) nodes.push_back(tet_edge_node(v[e], v[(e + 1) % 3]));
  return nodes;
}

// A distorted tetrahedron; for order 2 its edge nodes are moved off the midpoints by up to
// `curvature` (a curved isoparametric element). Node-major coordinates.
inline std::vector<double> distorted_tet(int order, double curvature = 0.06) {
  const Eigen::Vector3d v[4] = {
      {0.1, -0.05, 0.0}, {1.2, 0.1, -0.1}, {0.3, 0.9, 0.2}, {-0.1, 0.2, 1.1}};
  std::vector<double> X;
  for (const auto& p : v) X.insert(X.end(), {p(0), p(1), p(2)});
  if (order == 2) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> d(-curvature, curvature);
    for (const auto& e : kTetEdges) {
      const Eigen::Vector3d m = 0.5 * (v[e[0]] + v[e[1]]);
      X.insert(X.end(), {m(0) + d(rng), m(1) + d(rng), m(2) + d(rng)});
    }
  }
  return X;
}

inline std::vector<double> random_vector(size_t n, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> d(-amplitude, amplitude);
  std::vector<double> v(n);
  for (double& x : v) x = d(rng);
  return v;
}

// The cube [0,2]^3 as 2x2x2 unit cubes, each split into the 6 tetrahedra of the Kuhn
// triangulation (conforming across cubes), P1 or P2 with straight edges. The centre node is
// moved off its place and one node in the face x = 2 is moved within that face, so the
// elements are distorted but the boundary stays the six flat faces of the cube.
struct CubeMesh {
  int order = 1;
  std::vector<Eigen::Vector3d> x;
  std::vector<std::vector<int>> tets;            // nodes_per_tet node ids each
  std::vector<std::vector<int>> boundary_faces;  // outward Tri3/Tri6 node ids
  std::vector<bool> on_boundary;                 // per node
};

inline CubeMesh cube_mesh(int order) {
  CubeMesh mesh;
  mesh.order = order;
  auto id = [](int i, int j, int k) { return i + 3 * j + 9 * k; };
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) mesh.x.emplace_back(i, j, k);
  mesh.x[id(1, 1, 1)] += Eigen::Vector3d(0.15, -0.1, 0.12);
  mesh.x[id(2, 1, 1)] += Eigen::Vector3d(0.0, 0.12, -0.08);

  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int ck = 0; ck < 2; ++ck)
    for (int cj = 0; cj < 2; ++cj)
      for (int ci = 0; ci < 2; ++ci)
        for (const auto& p : perms) {
          int c[3] = {ci, cj, ck};
          std::vector<int> tet = {id(c[0], c[1], c[2])};
          for (int s = 0; s < 3; ++s) {
            ++c[p[s]];
            tet.push_back(id(c[0], c[1], c[2]));
          }
          const Eigen::Vector3d& x0 = mesh.x[tet[0]];
          Eigen::Matrix3d D;
          for (int s = 0; s < 3; ++s) D.col(s) = mesh.x[tet[s + 1]] - x0;
          if (D.determinant() < 0) std::swap(tet[1], tet[2]);
          mesh.tets.push_back(tet);
        }

  if (order == 2) {  // midpoint nodes, one per edge
    std::map<std::pair<int, int>, int> edge_node;
    for (auto& tet : mesh.tets) {
      const std::vector<int> v(tet.begin(), tet.begin() + 4);
      for (const auto& e : kTetEdges) {
        const auto key = std::minmax(v[e[0]], v[e[1]]);
        auto it = edge_node.find(key);
        if (it == edge_node.end()) {
          mesh.x.push_back(0.5 * (mesh.x[key.first] + mesh.x[key.second]));
          it = edge_node.emplace(key, static_cast<int>(mesh.x.size()) - 1).first;
        }
        tet.push_back(it->second);
      }
    }
  }

  // Boundary faces: those of exactly one tetrahedron.
  std::map<std::array<int, 3>, std::vector<int>> faces;
  for (const auto& tet : mesh.tets)
    for (int f = 0; f < 4; ++f) {
      std::vector<int> nodes;
      for (int a : face_nodes(order, f)) nodes.push_back(tet[a]);
      std::array<int, 3> key = {nodes[0], nodes[1], nodes[2]};
      std::sort(key.begin(), key.end());
      if (!faces.erase(key)) faces.emplace(key, nodes);
    }
  mesh.on_boundary.assign(mesh.x.size(), false);
  for (const auto& [key, nodes] : faces) {
    mesh.boundary_faces.push_back(nodes);
    for (int a : nodes) mesh.on_boundary[a] = true;
  }
  return mesh;
}

// Node-major coordinates (or any nodal vector field) of one element.
inline std::vector<double> gather(const std::vector<Eigen::Vector3d>& field,
                                  const std::vector<int>& nodes) {
  std::vector<double> out;
  for (int a : nodes) out.insert(out.end(), {field[a](0), field[a](1), field[a](2)});
  return out;
}

}  // namespace hs::testing_fixtures
