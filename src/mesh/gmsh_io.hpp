// Reading gmsh meshes (.msh 4.x) and meshing .geo sources through the gmsh C++ API.
#pragma once

#include <mpi.h>

#include "deck/config.hpp"
#include "mesh/mesh.hpp"

namespace hs {

// Reads cfg.file (.msh) or meshes it (.geo, with cfg.parameters set as geo numbers and
// cfg.refine uniform refinements), at element order cfg.order. Keeps tetrahedra and the
// named physical groups. Throws InputError naming the file and the reason (missing file,
// no tetrahedra, unsupported element type, a group without a name).
//
// .geo parameters: each must be declared in the file with DefineConstant[name = default]
// (a value set before the file is read wins over the default); a name the file never
// mentions, or a plain assignment that overwrites the value, is an error. A .msh (any
// version gmsh reads) of another order is converted (setOrder), after cfg.refine uniform
// refinements if any. gmsh is initialised and finalised inside each call, silently.
//
// Untrusted input (docs/reliability.md): a .geo is checked before gmsh runs it unless
// cfg.trust_geo (geo_guard.hpp: no commands, no writes, files read only from its folder and
// cfg.deck_dir); a .msh's counts are checked against its size before gmsh reads it
// (msh_prescan.hpp); more than cfg.max_elements tetrahedra (after cfg.refine) are refused,
// for a .geo before meshing when its size options already promise more, and after meshing; the
// loaded mesh is refused for non-finite coordinates, degenerate, inverted or overlapping tetrahedra
// and duplicated nodes (mesh_checks.hpp). Nothing is written to disk.
//
// On standard error (of the process that calls it: rank 0 of a run): a .geo's Printf lines, as
// "hydrosoft: FILE: TEXT", and a warning naming the worst tetrahedron when some are slivers
// (quality_warning in mesh_checks.hpp).
Mesh load_mesh(const MeshConfig& cfg);

// Throws InputError unless `name` is a group of the mesh with at least one node.
void require_group(const Mesh& mesh, const std::string& name, const std::string& where);

}  // namespace hs
