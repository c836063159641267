// dual_graph: each tetrahedron's four faces (sorted vertex triples) go to the rank their hash
// names; there two tetrahedra with the same triple are neighbours, and each learns of the
// other at the rank that holds its block. Memory per rank is its share of the faces.
#include <algorithm>
#include <array>

#include "common/exchange.hpp"
#include "mesh/mesh_distribute.hpp"

namespace hs {
namespace {

struct FaceKey {
  std::array<int64_t, 3> v;  // sorted vertices
  int64_t tet;
};

struct Edge {
  int64_t from, to;
};

}  // namespace

DualGraph dual_graph(const MeshSlab& slab, MPI_Comm comm) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  static const int kFace[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  const int npe = slab.nodes_per_tet();
  std::vector<std::vector<FaceKey>> keys(size);
  for (int64_t i = 0; i < slab.slab_tets(); ++i)
    for (const auto& face : kFace) {
      FaceKey k;
      for (int a = 0; a < 3; ++a) k.v[a] = slab.tets[npe * i + face[a]];
      std::sort(k.v.begin(), k.v.end());
      k.tet = slab.tet_begin + i;
      keys[face_rank(k.v, size)].push_back(k);
    }
  std::vector<FaceKey> mine = all_to_all(keys, comm);
  keys = {};
  std::sort(mine.begin(), mine.end(), [](const FaceKey& a, const FaceKey& b) {
    return a.v != b.v ? a.v < b.v : a.tet < b.tet;
  });
  std::vector<std::vector<Edge>> edges(size);
  for (size_t i = 0; i + 1 < mine.size(); ++i) {
    if (mine[i].v != mine[i + 1].v) continue;
    const int64_t a = mine[i].tet, b = mine[i + 1].tet;
    edges[block_owner(slab.num_tets, a, size)].push_back({a, b});
    edges[block_owner(slab.num_tets, b, size)].push_back({b, a});
  }
  mine = {};
  std::vector<Edge> in = all_to_all(edges, comm);
  std::sort(in.begin(), in.end(), [](const Edge& a, const Edge& b) {
    return a.from != b.from ? a.from < b.from : a.to < b.to;
  });
  DualGraph g;
  g.offsets.assign(slab.slab_tets() + 1, 0);
  for (const Edge& e : in) ++g.offsets[e.from - slab.tet_begin + 1];
  for (int64_t i = 0; i < slab.slab_tets(); ++i) g.offsets[i + 1] += g.offsets[i];
  g.neighbours.reserve(in.size());
  for (const Edge& e : in) g.neighbours.push_back(e.to);
  return g;
}

}  // namespace hs
