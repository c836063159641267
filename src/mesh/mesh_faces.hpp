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

struct MeshLabels;  // mesh_checks.hpp

// Renumbers the nodes of every tetrahedron with a negative vertex determinant so that
// det[x1 - x0, x2 - x0, x3 - x0] > 0 (swaps vertices 1 and 2 and the matching edge nodes).
// Throws InputError naming `file` and the element when a tetrahedron is degenerate (its
// volume below 1e-12 of the cube of its longest edge from vertex 0). A tetrahedron given
// with negative orientation is not an error: node order is a convention of the file.
void orient_tets_positively(Mesh& mesh, const std::string& file,
                            const MeshLabels* labels = nullptr);

// The faces of all tetrahedra, keyed by their sorted vertex ids. A face shared by two
// tetrahedra (an interior face) keeps the one with the lower index. Requires positively
// oriented tetrahedra: then the two tetrahedra of an interior face see it with opposite
// outward orientations, and overlap() reports the first face where that fails.
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
  // Two tetrahedra on the same side of a face they share, or sharing a face that a third
  // one has already: first = -1 when there are none.
  struct Overlap {
    int64_t first = -1, second = -1;
  };
  const Overlap& overlap() const { return overlap_; }

 private:
  struct KeyHash {
    size_t operator()(const std::array<int64_t, 3>& k) const;
  };
  struct Entry {
    Hit hit;
    int uses = 0;      // tetrahedra that have this face
    bool odd = false;  // the outward vertex order of hit.tet is an odd permutation of the key
  };
  std::unordered_map<std::array<int64_t, 3>, Entry, KeyHash> faces_;
  Overlap overlap_;
};

// Fills mesh.surfaces[name] and mesh.surface_tets[name] from triangles given by their three
// vertex ids (3 per triangle): each face is taken from the tetrahedron it bounds (its nodes,
// edge nodes included for P2, are that tetrahedron's), ordered so that its right-hand normal
// points out of that tetrahedron. Requires positively oriented tetrahedra. Throws InputError
// naming `file` and the group when a triangle bounds no tetrahedron.
void attach_surface(Mesh& mesh, const FaceIndex& index, const std::string& name,
                    const std::vector<int64_t>& triangles, const std::string& file);

}  // namespace hs
