// hydrosoft's mesh file (.h5): the result of meshing kept once, read by every rank in parallel
// (each rank reads its blocks; MeshSlab). Layout (docs/decks.md, "Meshing once"):
//   attributes of /: format = "hydrosoft mesh", version = 1, order = 1 or 2
//   /nodes                     N x 3 float64
//   /tets                      T x 4 or T x 10 int64 (0-based node numbers, gmsh's node order)
//   /tet_volume                T int32 (index of the tetrahedron's volume group)
//   /volumes/<name>            an empty group per volume, attribute index
//   /surfaces/<name>/faces     F x 3 or F x 6 int64, oriented out of the body
//   /surfaces/<name>/tets      F int64 (the tetrahedron each face bounds)
//   /node_groups/<name>        M int64, ascending
// It holds what load_mesh guarantees (mesh.hpp). The reader trusts none of it: every count is
// checked against the element limit and against what the file stores before anything is
// allocated, every number against the sizes before it is used, and the mesh as load_mesh
// checks a .msh (check_mesh_slab) before it is returned.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <string>

#include "mesh/mesh.hpp"
#include "mesh/mesh_slab.hpp"

namespace hs {

// Throws std::runtime_error naming the file on an HDF5 failure, InputError for a group name
// that HDF5 cannot hold ('/' or '.').
void write_mesh_h5(const Mesh& mesh, const std::string& path);

// Collective. Throws InputError (on every rank) naming the file and the dataset when the file
// is not a hydrosoft mesh, holds more than `max_elements` tetrahedra (mesh.max_elements), a
// dataset claims more than the file stores or a number is out of range, and naming the file
// and the element, node or face when the mesh fails check_mesh_slab (slab_checks.hpp).
MeshSlab read_mesh_h5(const std::string& path, int64_t max_elements, MPI_Comm comm);

}  // namespace hs
