// Checks of a loaded mesh that refuse it before any work, each naming the node or element at
// fault (docs/reliability.md, "Untrusted meshes and surfaces"), and the warnings of a mesh that
// looks drawn in other units than the deck's metres or holds slivers. Used by load_mesh; no gmsh
// needed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "mesh/mesh.hpp"
#include "mesh/mesh_faces.hpp"

namespace hs {

// How messages name nodes and tetrahedra: by their tags in the mesh file (gmsh's), when
// known, else by their index in the Mesh; always with their coordinates.
struct MeshLabels {
  std::vector<size_t> node_tags;  // per node of the Mesh, or empty
  std::vector<size_t> tet_tags;   // per tetrahedron of the Mesh, or empty

  std::string node(const Mesh& mesh, int64_t n) const;  // "node 12 at (0, 0, 1)"
  std::string tet(const Mesh& mesh, int64_t t) const;   // "element 7 (vertices ...)"
};

// Throws InputError "FILE: node N: reason" at the first node with a NaN or infinite
// coordinate (a number that overflowed a double reads as infinite).
void check_finite_coordinates(const Mesh& mesh, const std::string& file,
                              const MeshLabels& labels = {});

// P2 only: throws InputError naming the element whose map from the reference tetrahedron has
// a non-positive Jacobian at one of its nodes or at a quadrature point of the element
// routines (an edge node pulled across the element: inverted, or curved too strongly).
// Requires positively oriented vertices (orient_tets_positively).
void check_curved_tets(const Mesh& mesh, const std::string& file, const MeshLabels& labels = {});

// Throws InputError naming both nodes when two distinct nodes lie at the same place (to
// 1e-12 of the mesh's extent): the tetrahedra on either side are then not connected (a
// crack, or a volume meshed twice), which the run would silently treat as two bodies.
void check_duplicate_nodes(const Mesh& mesh, const std::string& file,
                           const MeshLabels& labels = {});

// Throws InputError naming both elements when a face is shared by two tetrahedra on the same
// side of it, or by more than two: tetrahedra that overlap (one folded over its neighbour).
void check_no_overlap(const Mesh& mesh, const FaceIndex& faces, const std::string& file,
                      const MeshLabels& labels = {});

// The mean-ratio quality (mesh_statistics.hpp) below which a tetrahedron draws a warning. A
// tetrahedron flattened to a sliver has quality q when the map from a regular one squashes one
// direction to (2q/3)^(3/2) of the others: 1/650 at 0.02, so its stiffness is some 4e5 times
// worse conditioned and its strains carry the error of a nearly singular map. The shipped
// meshes, as gmsh makes them, stay at 0.047 or above (the pendulum's; most above 0.28), so the
// warning is for slivers, not for the ordinary spread of a gmsh mesh.
constexpr double kPoorTetQuality = 0.02;

// Empty, or a one-line warning naming `file`, the worst-shaped tetrahedron (by its tag in the
// file), its quality and how many tetrahedra are below kPoorTetQuality, and why that matters.
// A warning, not an error: a sliver in a part of the body whose numbers do not matter is the
// user's choice. P2: the quality of the corner tetrahedron.
std::string quality_warning(const Mesh& mesh, const std::string& file,
                            const MeshLabels& labels = {});

// Empty, or a warning naming `file` and the bounding box when the mesh's largest extent is
// above 100 m or below 1e-4 m: likely a mesh drawn in millimetres (or in metres under a deck
// meant in millimetres); the deck's numbers are SI.
std::string units_warning(const Mesh& mesh, const std::string& file);

}  // namespace hs
