#include "mesh/mesh_faces.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/error.hpp"
#include "mesh/mesh_checks.hpp"
#include "mesh/tet_numbering.hpp"

namespace hs {
namespace {

using tet::kEdgeNode;
using tet::kOutwardFace;
using tet::node_x;
using tet::odd_order;

// Swapping vertices 1 and 2 of a tetrahedron: new node i is old node kSwap12[i]. The edge
// nodes follow their edges, e.g. new edge (0, 1) is old edge (0, 2), node 6.
constexpr int kSwap12[10] = {0, 2, 1, 3, 6, 5, 4, 7, 9, 8};

}  // namespace

void orient_tets_positively(Mesh& mesh, const std::string& file, const MeshLabels* labels) {
  const int npe = mesh.nodes_per_tet();
  int64_t tet_copy[10];
  for (int64_t t = 0; t < mesh.num_tets(); ++t) {
    int64_t* tet = &mesh.tets[t * npe];
    const Eigen::Vector3d x0 = node_x(mesh, tet[0]);
    Eigen::Matrix3d edges;
    for (int i = 0; i < 3; ++i) edges.col(i) = node_x(mesh, tet[i + 1]) - x0;
    const double det = edges.determinant();
    // Degenerate relative to the cube of the longest vertex-to-vertex-0 edge.
    const double scale = edges.colwise().norm().maxCoeff();
    if (!(std::abs(det) > 1e-12 * scale * scale * scale))
      throw InputError(file + ": " + (labels ? *labels : MeshLabels{}).tet(mesh, t) +
                       " is degenerate (zero volume)");
    if (det > 0) continue;
    std::copy(tet, tet + npe, tet_copy);
    for (int i = 0; i < npe; ++i) tet[i] = tet_copy[kSwap12[i]];
  }
}

size_t FaceIndex::KeyHash::operator()(const std::array<int64_t, 3>& k) const {
  // Boost-style hash combination of the three sorted vertex ids.
  size_t h = 0;
  for (int64_t v : k) h ^= std::hash<int64_t>()(v) + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
  return h;
}

FaceIndex::FaceIndex(const Mesh& mesh) {
  const int npe = mesh.nodes_per_tet();
  faces_.reserve(static_cast<size_t>(2.2 * static_cast<double>(mesh.num_tets())) + 16);
  for (int64_t t = 0; t < mesh.num_tets(); ++t) {
    const int64_t* tet = &mesh.tets[t * npe];
    for (int v = 0; v < 4; ++v) {
      const int* f = kOutwardFace[v];
      std::array<int64_t, 3> key{tet[f[0]], tet[f[1]], tet[f[2]]};
      const bool odd = odd_order(key[0], key[1], key[2]);
      std::sort(key.begin(), key.end());
      auto [it, inserted] = faces_.emplace(key, Entry{Hit{t, v}, 1, odd});  // keeps the lowest
      if (inserted) continue;
      Entry& e = it->second;
      // A second tetrahedron must see the face the other way round, and none may be third.
      if (overlap_.first < 0 && (++e.uses > 2 || e.odd == odd)) overlap_ = {e.hit.tet, t};
    }
  }
}

FaceIndex::Hit FaceIndex::find(int64_t a, int64_t b, int64_t c) const {
  std::array<int64_t, 3> key{a, b, c};
  std::sort(key.begin(), key.end());
  const auto it = faces_.find(key);
  return it == faces_.end() ? Hit{} : it->second.hit;
}

void attach_surface(Mesh& mesh, const FaceIndex& index, const std::string& name,
                    const std::vector<int64_t>& triangles, const std::string& file) {
  const int npe = mesh.nodes_per_tet();
  auto& faces = mesh.surfaces[name];
  auto& face_tets = mesh.surface_tets[name];
  faces.clear();
  face_tets.clear();
  for (size_t i = 0; i + 2 < triangles.size(); i += 3) {
    const auto hit = index.find(triangles[i], triangles[i + 1], triangles[i + 2]);
    if (hit.tet < 0) {
      std::ostringstream msg;
      msg << file << ": surface group '" << name << "': the triangle with a vertex at "
          << node_x(mesh, triangles[i]).transpose() << " bounds no tetrahedron";
      throw InputError(msg.str());
    }
    const int64_t* tet = &mesh.tets[hit.tet * npe];
    const int* f = kOutwardFace[hit.opposite];
    for (int k = 0; k < 3; ++k) faces.push_back(tet[f[k]]);
    if (mesh.order == 2)
      for (int k = 0; k < 3; ++k) faces.push_back(tet[kEdgeNode[f[k]][f[(k + 1) % 3]]]);
    face_tets.push_back(hit.tet);
  }
}

}  // namespace hs
