// Helpers of the mesh tests: loading the shipped .geo sources, temporary folders, and
// reference geometry (tetrahedron volumes, face area vectors) written independently of
// the library.
#pragma once

#include <gtest/gtest.h>
#include <stdlib.h>

#include <Eigen/Dense>
#include <array>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "deck/config.hpp"
#include "mesh/gmsh_io.hpp"
#include "mesh/mesh.hpp"

namespace hs::test {

using Vec3 = Eigen::Vector3d;

inline std::string source_mesh(const std::string& name) {
  return std::string(HYDROSOFT_SOURCE_DIR) + "/meshes/" + name;
}

inline Mesh load_geo(const std::string& name, std::map<std::string, double> parameters,
                     int order = 1, int refine = 0) {
  MeshConfig cfg;
  cfg.file = source_mesh(name);
  cfg.parameters = std::move(parameters);
  cfg.order = order;
  cfg.refine = refine;
  return load_mesh(cfg);
}

// A fresh folder under the system's temporary directory, removed with the object.
class TempDir {
 public:
  TempDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "hs_mesh_test_XXXXXX").string();
    path_ = mkdtemp(pattern.data());
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  std::string file(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

inline Vec3 node(const Mesh& m, int64_t n) {
  return Vec3(m.x[3 * n], m.x[3 * n + 1], m.x[3 * n + 2]);
}

// Volume of a straight-sided tetrahedron from its four vertices.
inline double vertex_volume(const Mesh& m, int64_t t) {
  const int64_t* v = &m.tets[t * m.nodes_per_tet()];
  const Vec3 x0 = node(m, v[0]);
  return (node(m, v[1]) - x0).cross(node(m, v[2]) - x0).dot(node(m, v[3]) - x0) / 6;
}

// Volume of a P2 (possibly curved) tetrahedron: the integral of det(dx/dxi) over the
// reference tetrahedron. det is a cubic, so the 5-point degree-3 rule is exact.
inline double p2_volume(const Mesh& m, int64_t t) {
  const int64_t* v = &m.tets[t * 10];
  // Edge node of each pair of vertices, gmsh order (see mesh.hpp).
  const int edge[4][4] = {{-1, 4, 6, 7}, {4, -1, 5, 9}, {6, 5, -1, 8}, {7, 9, 8, -1}};
  const double a = 1.0 / 6, b = 0.5;
  const std::array<std::array<double, 4>, 5> points = {
      {{0.25, 0.25, 0.25, 0.25}, {b, a, a, a}, {a, b, a, a}, {a, a, b, a}, {a, a, a, b}}};
  const std::array<double, 5> weights = {-4.0 / 5, 9.0 / 20, 9.0 / 20, 9.0 / 20, 9.0 / 20};
  double volume = 0;
  for (int q = 0; q < 5; ++q) {
    const auto& L = points[q];  // barycentric coordinates; xi_k = L[k + 1]
    // dN/dL: vertex i: 4 L_i - 1; edge (i, j): 4 L_j along L_i and 4 L_i along L_j.
    // d/dxi_k = d/dL_{k+1} - d/dL_0.
    Eigen::Matrix3d J = Eigen::Matrix3d::Zero();
    auto add = [&](int n, int i, double dN_dLi) {
      const Vec3 x = node(m, v[n]);
      if (i == 0)
        for (int k = 0; k < 3; ++k) J.col(k) -= dN_dLi * x;
      else
        J.col(i - 1) += dN_dLi * x;
    };
    for (int i = 0; i < 4; ++i) add(i, i, 4 * L[i] - 1);
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        add(edge[i][j], i, 4 * L[j]);
        add(edge[i][j], j, 4 * L[i]);
      }
    volume += weights[q] * J.determinant() / 6;
  }
  return volume;
}

inline double mesh_volume(const Mesh& m) {
  double v = 0;
  for (int64_t t = 0; t < m.num_tets(); ++t)
    v += m.order == 1 ? vertex_volume(m, t) : p2_volume(m, t);
  return v;
}

// Area vector of the straight triangle through a face's three vertices (right-hand rule).
inline Vec3 face_area_vector(const Mesh& m, const std::string& group, int64_t f) {
  const int64_t* v = &m.surfaces.at(group)[f * m.nodes_per_face()];
  const Vec3 x0 = node(m, v[0]);
  return 0.5 * (node(m, v[1]) - x0).cross(node(m, v[2]) - x0);
}

inline Vec3 face_centroid(const Mesh& m, const std::string& group, int64_t f) {
  const int64_t* v = &m.surfaces.at(group)[f * m.nodes_per_face()];
  return (node(m, v[0]) + node(m, v[1]) + node(m, v[2])) / 3;
}

inline int64_t num_faces(const Mesh& m, const std::string& group) {
  return static_cast<int64_t>(m.surfaces.at(group).size()) / m.nodes_per_face();
}

// A gmsh 4.1 ASCII file with one entity per dimension (tag 1), each optionally in a
// named physical group (tag = 10 + dim), and all nodes classified on the volume.
struct MshFile {
  std::vector<std::array<double, 3>> nodes;  // node tags 1, 2, ...
  struct Block {
    int dim, type;
    std::vector<std::vector<int>> elements;  // node tags
  };
  std::vector<Block> blocks;
  std::map<int, std::string> group_of_dim;

  std::string write(const TempDir& dir, const std::string& name) const {
    std::ostringstream s;
    s << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n" << group_of_dim.size() << "\n";
    for (const auto& [dim, g] : group_of_dim) s << dim << " " << 10 + dim << " \"" << g << "\"\n";
    s << "$EndPhysicalNames\n$Entities\n";
    int count[4] = {0, 0, 0, 0};
    for (const auto& b : blocks) count[b.dim] = 1;
    s << count[0] << " " << count[1] << " " << count[2] << " " << count[3] << "\n";
    auto physical = [&](int dim) {
      return group_of_dim.count(dim) ? "1 " + std::to_string(10 + dim) : std::string("0");
    };
    for (const auto& b : blocks) {
      if (b.dim == 0) {
        const auto& x = nodes[b.elements[0][0] - 1];
        s << "1 " << x[0] << " " << x[1] << " " << x[2] << " " << physical(0) << "\n";
      }
    }
    for (int dim = 1; dim <= 3; ++dim)
      if (count[dim]) s << "1 -10 -10 -10 10 10 10 " << physical(dim) << " 0\n";
    s << "$EndEntities\n$Nodes\n1 " << nodes.size() << " 1 " << nodes.size() << "\n3 1 0 "
      << nodes.size() << "\n";
    for (size_t i = 0; i < nodes.size(); ++i) s << i + 1 << "\n";
    for (const auto& x : nodes) s << x[0] << " " << x[1] << " " << x[2] << "\n";
    size_t total = 0;
    for (const auto& b : blocks) total += b.elements.size();
    s << "$EndNodes\n$Elements\n" << blocks.size() << " " << total << " 1 " << total << "\n";
    int tag = 1;
    for (const auto& b : blocks) {
      s << b.dim << " 1 " << b.type << " " << b.elements.size() << "\n";
      for (const auto& e : b.elements) {
        s << tag++;
        for (int n : e) s << " " << n;
        s << "\n";
      }
    }
    s << "$EndElements\n";
    const std::string path = dir.file(name);
    std::ofstream(path) << s.str();
    return path;
  }
};

// The unit corner tetrahedron, given with negative orientation (vertices 1 and 2 swapped),
// its face z = 0 as group "base" and its apex (0, 0, 1) as point group "apex".
inline MshFile corner_tet() {
  MshFile f;
  f.nodes = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  f.blocks = {{0, 15, {{4}}}, {2, 2, {{1, 2, 3}}}, {3, 4, {{1, 3, 2, 4}}}};
  f.group_of_dim = {{0, "apex"}, {2, "base"}, {3, "solid"}};
  return f;
}

// Runs `body` and expects an InputError whose message contains every one of `parts`.
template <typename F>
void expect_input_error(F body, const std::vector<std::string>& parts) {
  try {
    body();
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    for (const auto& p : parts)
      EXPECT_NE(std::string(e.what()).find(p), std::string::npos)
          << "'" << p << "' not in: " << e.what();
  }
}

}  // namespace hs::test
