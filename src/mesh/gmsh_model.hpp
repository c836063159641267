// The step from gmsh's current model (already meshed, at the wanted order) to a Mesh.
// Internal to load_mesh (gmsh_io.cpp); needs an initialised gmsh.
#pragma once

#include <string>

#include "mesh/mesh.hpp"

namespace hs {

// Throws InputError naming `file` when the model has 3D elements other than tetrahedra.
void check_tetrahedra_only(const std::string& file);

// Reads the tetrahedra of gmsh's current model (all of order `order`) and its named physical
// groups into a Mesh with compact node numbering. `file` names the source in error messages.
//
// Volume groups: every tetrahedron must lie in exactly one named volume group; a model
// with no volume group at all gets one default group "body" holding every tetrahedron
// (and the node group "body"). A tetrahedron in no volume group, or in two, is an error.
// Surface groups: triangles only, each bounding a tetrahedron (see attach_surface).
// Node groups: one per named group of any dimension; every node must be a tetrahedron's.
// Refused, naming the node or element by its tag: a coordinate that is not finite, a
// degenerate tetrahedron, a P2 tetrahedron with a non-positive Jacobian, two nodes at the
// same place, two tetrahedra that overlap (mesh_checks.hpp).
Mesh mesh_from_gmsh_model(const std::string& file, int order);

}  // namespace hs
