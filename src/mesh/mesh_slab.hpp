// A mesh as the ranks read it, before it is partitioned: rank r holds one contiguous block of
// the nodes, of the tetrahedra, of each surface group's faces and of each node group, all in
// the numbers of the mesh file. No rank holds more than its blocks, so reading scales with the
// ranks; distribute_slabs (mesh_distribute.hpp) then moves every tetrahedron to its part.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "mesh/mesh.hpp"

namespace hs {

struct MeshSlab {
  std::string file;  // the mesh file it came from, named by messages
  int order = 1;
  int64_t num_nodes = 0, num_tets = 0;    // of the whole mesh
  int64_t node_begin = 0, tet_begin = 0;  // the first node and tetrahedron of this block
  std::vector<double> x;                  // coordinates of this block's nodes, 3 each
  std::vector<int64_t> tets;              // this block's tetrahedra, nodes_per_tet() each
  std::vector<int> tet_volume;            // per tetrahedron: index into groups.volumes
  MeshGroups groups;
  struct Faces {
    int64_t begin = 0;           // index in the whole group of the first face here
    std::vector<int64_t> nodes;  // nodes_per_face() each
    std::vector<int64_t> tets;   // the tetrahedron each bounds
  };
  std::map<std::string, Faces> surfaces;                    // every surface group
  std::map<std::string, std::vector<int64_t>> node_groups;  // a block of each group's nodes

  int nodes_per_tet() const { return order == 1 ? 4 : 10; }
  int nodes_per_face() const { return order == 1 ? 3 : 6; }
  int64_t slab_nodes() const { return static_cast<int64_t>(x.size() / 3); }
  int64_t slab_tets() const { return static_cast<int64_t>(tets.size()) / nodes_per_tet(); }
};

// Rank `rank`'s blocks of a whole mesh. Pure.
MeshSlab slab_of(const Mesh& mesh, int rank, int size);

// The whole mesh from a slab that holds all of it (read on one process). Pure.
Mesh whole_mesh(const MeshSlab& slab);

// Collective: the root holds `mesh` (the other ranks pass nullptr) and sends every rank its
// blocks; the root keeps its own.
MeshSlab scatter_mesh(const Mesh* mesh, int root, MPI_Comm comm);

}  // namespace hs
