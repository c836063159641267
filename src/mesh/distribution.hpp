// How the mesh is spread over MPI ranks: every rank assembles the tetrahedra of its part; nodes are
// renumbered so that each rank owns a contiguous range of the new global numbering (the PETSc
// layout, 3 dofs per node); the nodes of a rank's tetrahedra that other ranks own are its ghosts. A
// node is owned by the lowest part among the tetrahedra that contain it; inside a rank, new ids
// keep the mesh order of the nodes.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "mesh/mesh.hpp"

namespace hs {

struct Distribution {
  int rank = 0, size = 1;
  int order = 1;                       // 1 (Tet4) or 2 (Tet10)
  int64_t num_global_tets = 0;         // of the whole mesh
  std::vector<int64_t> owned_offsets;  // size+1 entries: rank r owns new ids [off[r], off[r+1])
  std::vector<int64_t> local_nodes;    // new global ids of this rank's local nodes: owned
                                       // ones first, ascending, then ghosts, ascending
  std::vector<int64_t> old_of_local;   // number in the mesh file of each local node
  std::vector<double> x;               // reference coordinates of the local nodes, 3 each
  std::vector<int64_t> local_tets;     // numbers in the mesh file of the local tetrahedra,
                                       // ascending
  std::vector<int32_t> tet_nodes;      // local node index of each node of each local tet
  std::vector<int> tet_volume;         // per local tet: index into groups.volumes
  MeshGroups groups;                   // names and sizes of the whole mesh's groups
  // Per surface group (every group of the mesh, maybe empty here): the faces whose
  // tetrahedron is local, in local node indices, and each one's index in the whole group.
  std::map<std::string, std::vector<int32_t>> faces;
  std::map<std::string, std::vector<int64_t>> face_index;
  // Per named group: its nodes that are local (owned or ghost), in local node indices.
  std::map<std::string, std::vector<int32_t>> node_groups;

  int64_t num_owned() const { return owned_offsets[rank + 1] - owned_offsets[rank]; }
  int64_t num_local() const { return static_cast<int64_t>(local_nodes.size()); }
  int64_t num_global() const { return owned_offsets.back(); }
  int nodes_per_tet() const { return order == 1 ? 4 : 10; }
  int nodes_per_face() const { return order == 1 ? 3 : 6; }
};

// The piece of a whole mesh that `rank` of `size` works on, for a given partition of its
// tetrahedra. Pure (no MPI): the simple reference that the parallel construction
// (distribute_slabs, which no rank needs the whole mesh for) is tested against.
Distribution distribute(const Mesh& mesh, const std::vector<int>& tet_part, int rank, int size);

}  // namespace hs
