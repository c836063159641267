// Topology helpers of the global mesh that need no gmsh: tetrahedron orientation and the
// matching of boundary triangles to the tetrahedra they bound. Used by load_mesh.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "mesh/mesh.hpp"

namespace hs {

// Renumbers the nodes of every tetrahedron with a negative vertex determinant so that
// det[x1 - x0, x2 - x0, x3 - x0] > 0 (swaps vertices 1 and 2 and the matching edge nodes).
// Throws InputError naming `file` and the element when a tetrahedron is degenerate.
void orient_tets_positively(Mesh& mesh, const std::string& file);

// The faces of all tetrahedra, keyed by their sorted vertex ids. A face shared by two
// tetrahedra (an interior face) keeps the one with the lower index.
class FaceIndex {
 public:
  explicit FaceIndex(const Mesh& mesh);
  // The tetrahedron bounded by the face with these vertices and the local index (0..3) of
  // its vertex opposite the face; tet = -1 when no tetrahedron has this face.
  struct Hit {
    int64_t tet = -1;
    int opposite = -1;
  };
  Hit find(int64_t a, int64_t b, int64_t c) const;

 private:
  struct KeyHash {
    size_t operator()(const std::array<int64_t, 3>& k) const;
  };
  std::unordered_map<std::array<int64_t, 3>, Hit, KeyHash> faces_;
};

// Fills mesh.surfaces[name] and mesh.surface_tets[name] from triangles given by their three
// vertex ids (3 per triangle): each face is taken from the tetrahedron it bounds (its nodes,
// edge nodes included for P2, are that tetrahedron's), ordered so that its right-hand normal
// points out of that tetrahedron. Requires positively oriented tetrahedra. Throws InputError
// naming `file` and the group when a triangle bounds no tetrahedron.
void attach_surface(Mesh& mesh, const FaceIndex& index, const std::string& name,
                    const std::vector<int64_t>& triangles, const std::string& file);

}  // namespace hs
