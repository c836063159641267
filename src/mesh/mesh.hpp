// The global tetrahedral mesh: nodes, P1 or P2 tetrahedra, and the named physical
// groups of gmsh (volumes = materials, surfaces = boundaries, loaded faces, cavities).
//
// Node ordering inside an element follows gmsh:
//   Tet4:  0 1 2 3
//   Tet10: vertices 0..3, then edge nodes 4:(0,1) 5:(1,2) 6:(2,0) 7:(3,0) 8:(3,2) 9:(3,1)
//   Tri3:  0 1 2
//   Tri6:  vertices 0..2, then edge nodes 3:(0,1) 4:(1,2) 5:(2,0)
//
// What load_mesh guarantees: nodes are exactly the nodes of the tetrahedra (numbered in
// gmsh tag order); every tetrahedron is positively oriented, det[x1-x0, x2-x0, x3-x0] > 0;
// every tetrahedron is in exactly one volume group (a mesh without volume groups gets the
// single group "body"); a surface face is made of the nodes of the tetrahedron it bounds
// (for a face shared by two tetrahedra, an interior surface, the one of lower index).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace hs {

struct Mesh {
  int order = 1;                // 1 (Tet4) or 2 (Tet10)
  std::vector<double> x;        // reference coordinates, 3 per node
  std::vector<int64_t> tets;    // nodes_per_tet() per tetrahedron
  std::vector<int> tet_volume;  // per tetrahedron: index into volume_names
  std::vector<std::string> volume_names;
  // Per named surface group: its triangles, nodes_per_face() each, oriented so that the
  // right-hand normal points out of the body (away from the tetrahedron they bound).
  std::map<std::string, std::vector<int64_t>> surfaces;
  // Per named surface group: for each of its triangles, the tetrahedron it bounds.
  std::map<std::string, std::vector<int64_t>> surface_tets;
  // Per named group of any dimension (point, curve, surface, volume): its sorted nodes.
  std::map<std::string, std::vector<int64_t>> node_groups;

  int nodes_per_tet() const { return order == 1 ? 4 : 10; }
  int nodes_per_face() const { return order == 1 ? 3 : 6; }
  int64_t num_nodes() const { return static_cast<int64_t>(x.size() / 3); }
  int64_t num_tets() const { return static_cast<int64_t>(tets.size()) / nodes_per_tet(); }
};

// The named groups of a mesh and their sizes, which every rank knows even when it holds a
// part of the mesh only: what a deck's group names are checked against.
struct MeshGroups {
  std::vector<std::string> volumes;
  std::map<std::string, int64_t> surface_faces;  // per surface group: its number of faces
  std::map<std::string, int64_t> group_nodes;    // per named group: its number of nodes
};

MeshGroups groups_of(const Mesh& mesh);

}  // namespace hs
