// How the global mesh is spread over MPI ranks: every rank assembles the tetrahedra of
// its METIS part; nodes are renumbered so that each rank owns a contiguous range of the
// new global numbering (the PETSc layout, 3 dofs per node); the nodes of a rank's
// tetrahedra that other ranks own are its ghosts. A node is owned by the lowest part among
// the tetrahedra that contain it; inside a rank, new ids keep the mesh order of the nodes.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "mesh/mesh.hpp"

namespace hs {

struct Distribution {
  int rank = 0, size = 1;
  std::vector<int64_t> new_of_old;     // global renumbering of all nodes: new id of old node
  std::vector<int64_t> owned_offsets;  // size+1 entries: rank r owns new ids [off[r], off[r+1])
  std::vector<int64_t> local_nodes;    // new global ids of this rank's local nodes: owned
                                       // ones first, ascending, then ghosts, ascending
  std::vector<int64_t> old_of_local;   // old (mesh) id of each local node
  std::vector<int64_t> local_tets;     // mesh indices of the tetrahedra this rank assembles
  std::vector<int32_t> tet_nodes;      // local node index of each node of each local tet
  // Per surface group: the faces whose tetrahedron is local, in local node indices.
  std::map<std::string, std::vector<int32_t>> faces;
  // Per named group: its nodes that are local (owned or ghost), in local node indices.
  std::map<std::string, std::vector<int32_t>> node_groups;

  int64_t num_owned() const { return owned_offsets[rank + 1] - owned_offsets[rank]; }
  int64_t num_local() const { return static_cast<int64_t>(local_nodes.size()); }
  int64_t num_global() const { return owned_offsets.back(); }
};

// A METIS partition of the tetrahedra (dual graph: tets sharing a face) into nparts parts.
// Deterministic; nparts == 1 puts everything in part 0.
std::vector<int> partition_tets(const Mesh& mesh, int nparts);

// The piece of the mesh that `rank` of `size` works on, for a given partition.
// Pure (no MPI), so that every rank's piece can be tested on one process.
Distribution distribute(const Mesh& mesh, const std::vector<int>& tet_part, int rank, int size);

}  // namespace hs
