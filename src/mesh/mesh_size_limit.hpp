// The limit on the tetrahedra of a mesh, mesh.max_elements (docs/reliability.md, "Untrusted
// meshes and surfaces"). The limit counts tetrahedra after cfg.refine uniform refinements (8
// each). Each check throws InputError "FILE: mesh.max_elements: what, above the limit of N
// tetrahedra (...)". Needs an initialised gmsh with the model loaded (check_tet_count does not).
#pragma once

#include <string>

#include "deck/config.hpp"

namespace hs {

// Before meshing: refuses the model when a lower bound on its tetrahedra, from its size
// options, its curves' length, its surfaces' area and its volume, is above the limit.
void check_size_estimate(const MeshConfig& cfg);

// Refuses `tets` tetrahedra (before refinement) above the limit; `what` says whose they are.
void check_tet_count(const MeshConfig& cfg, double tets, const std::string& what);

// After meshing (or reading): refuses the model's tetrahedra above the limit.
void check_meshed_tet_count(const MeshConfig& cfg);

}  // namespace hs
