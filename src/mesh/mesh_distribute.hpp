// The parallel way from the blocks the ranks read (MeshSlab) to each rank's piece of the mesh
// (Distribution), without any rank holding the whole mesh or an array over all of its nodes:
//   dual_graph        which tetrahedra share a face (for the partitioner), by hashing faces
//                     to the rank that matches them;
//   distribute_slabs  every tetrahedron (and the faces it bounds) moved to its part; node
//                     owners agreed at each node's block; owned nodes numbered by exclusive
//                     scan; ghosts' numbers asked from their owners.
// The result is the same Distribution as distribute(mesh, part, rank, size) for the same
// partition (tests/mesh/mpi_test_mesh_distribute.cpp checks it field by field).
#pragma once

#include <mpi.h>

#include <array>
#include <cstdint>
#include <vector>

#include "mesh/distribution.hpp"
#include "mesh/mesh_slab.hpp"

namespace hs {

// splitmix64's finaliser: spreads nearby keys (node numbers, cells) evenly over the ranks
// when taken modulo their number.
inline uint64_t spread(uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// The rank of `size` that matches the faces with these sorted vertices.
inline int face_rank(const std::array<int64_t, 3>& v, int size) {
  return static_cast<int>(spread(spread(spread(v[0]) ^ v[1]) ^ v[2]) % size);
}

// CSR rows for the slab's tetrahedra: the mesh numbers of their face neighbours, ascending.
struct DualGraph {
  std::vector<int64_t> offsets;  // slab_tets() + 1
  std::vector<int64_t> neighbours;
};

// Collective.
DualGraph dual_graph(const MeshSlab& slab, MPI_Comm comm);

// Collective: this rank's piece of the mesh when the slab's tetrahedron i goes to part
// part[i]. Throws InputError (on every rank) for a node in no tetrahedron or a tetrahedron
// that is inverted or degenerate, naming slab.file and the node or tetrahedron by its number
// in it.
Distribution distribute_slabs(const MeshSlab& slab, const std::vector<int>& part, MPI_Comm comm);

}  // namespace hs
