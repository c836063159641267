// What `hydrosoft --check` says of a mesh before any solve: its size, extent, smallest and
// worst-shaped elements and the volumes its closed surface groups enclose.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "mesh/mesh.hpp"

namespace hs {

struct MeshStatistics {
  int order = 1;
  int64_t nodes = 0, tets = 0;
  std::array<double, 3> lower{}, upper{};  // bounding box (m)
  int64_t smallest_tet = -1;               // the tetrahedron of least volume, and that volume
  double smallest_volume = 0;
  // Shape by the mean ratio of the corner tetrahedron, q = 12 (3 V)^(2/3) / sum of squared
  // edges: 1 for a regular tetrahedron, -> 0 as it flattens. The worst one and its q.
  int64_t worst_tet = -1;
  double worst_quality = 0;
  std::map<std::string, double> enclosed_volumes;  // per requested surface group (m^3)
};

// The statistics of `mesh`, with the volume enclosed by each of `closed_groups` (surface
// groups whose faces point out of the body, e.g. cavities) in the reference configuration.
MeshStatistics mesh_statistics(const Mesh& mesh, const std::vector<std::string>& closed_groups);

// Mean-ratio quality of the tetrahedron with corners a, b, c, d (3 coordinates each).
double tet_quality(const double* a, const double* b, const double* c, const double* d);

// Lines for people, e.g. "nodes 1234, tetrahedra 5678 (P1), dofs 3702".
std::string format_statistics(const MeshStatistics& s);

}  // namespace hs
