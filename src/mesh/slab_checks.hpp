// The checks that load_mesh makes of a .msh (mesh_checks.hpp, attach_surface), made of a mesh
// read in blocks (an .h5 mesh file: read_mesh_h5) without any rank holding more than its
// blocks and what it is sent about them (docs/reliability.md, "Untrusted meshes and
// surfaces"). Faces go to the rank their vertices hash to, as in dual_graph; nodes to the rank
// of their cell in space; a surface face to the rank that holds the block of the tetrahedron
// it bounds. Time and memory per rank grow with its share of the mesh (a sort of it at most).
#pragma once

#include <mpi.h>

#include "mesh/mesh_slab.hpp"

namespace hs {

// Collective. Throws InputError on every rank, naming slab.file and the element, node or face
// by its row in the file (the first found on the lowest rank that finds one), when
//   - a node belongs to no tetrahedron;
//   - a tetrahedron is degenerate (zero volume), inverted (its vertices in negative order:
//     hydrosoft writes them positive) or, in P2, has a Jacobian that is not positive at a node
//     or a quadrature point (check_curved_tets);
//   - two nodes lie within 1e-12 of the mesh's extent of each other (check_duplicate_nodes);
//   - two tetrahedra share a face and lie on the same side of it, or three share one;
//   - a surface face is not a face of the tetrahedron that its group's tets names, is listed
//     inwards (hydrosoft writes them outwards: the pressure on it would push the wrong way),
//     or, in P2, has edge nodes other than that tetrahedron's.
// Requires what read_mesh_h5 checks as it reads: node and tetrahedron numbers in range,
// finite coordinates.
void check_mesh_slab(const MeshSlab& slab, MPI_Comm comm);

}  // namespace hs
