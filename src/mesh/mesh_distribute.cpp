// distribute_slabs: the rules are distribute()'s (distribution.hpp); here every step is a
// personalised exchange, so that each rank stores only what concerns its own tetrahedra and
// its own blocks. A node's block (block_owner over the nodes) is where its owner is decided,
// its coordinates and its groups are kept, and where ranks ask for them.
#include "mesh/mesh_distribute.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "common/error.hpp"
#include "common/exchange.hpp"

namespace hs {
namespace {

struct TetRecord {
  int64_t id;
  int32_t volume;
  int64_t nodes[10];
};

struct FaceRecord {
  int64_t tet, index;  // the tetrahedron it bounds; its index in the whole group
  int32_t group;       // index among the slab's surface groups (a std::map: same order
                       // on every rank)
  int64_t nodes[6];
};

struct NodeInGroup {
  int64_t node;
  int32_t group;
};

struct NodeReply {
  int32_t owner;
  double x[3];
};

struct NewId {
  int64_t node, id;
};

template <class T>
int64_t position(const std::vector<T>& sorted, T value) {
  return std::lower_bound(sorted.begin(), sorted.end(), value) - sorted.begin();
}

// The slab's faces, moved to the rank of their tetrahedron's part (through the rank that
// holds the tetrahedron's block and knows its part).
std::vector<FaceRecord> faces_to_parts(const MeshSlab& slab, const std::vector<int>& part,
                                       MPI_Comm comm, int size) {
  const int npf = slab.nodes_per_face();
  std::vector<std::vector<FaceRecord>> out(size);
  int32_t g = 0;
  for (const auto& [name, faces] : slab.surfaces) {
    for (size_t f = 0; f < faces.tets.size(); ++f) {
      FaceRecord r{faces.tets[f], faces.begin + static_cast<int64_t>(f), g, {}};
      std::copy_n(&faces.nodes[npf * f], npf, r.nodes);
      out[block_owner(slab.num_tets, r.tet, size)].push_back(r);
    }
    ++g;
  }
  const std::vector<FaceRecord> at_block = all_to_all(out, comm);
  out.assign(size, {});
  for (const FaceRecord& r : at_block) out[part[r.tet - slab.tet_begin]].push_back(r);
  std::vector<FaceRecord> mine = all_to_all(out, comm);
  std::sort(mine.begin(), mine.end(), [](const FaceRecord& a, const FaceRecord& b) {
    return a.group != b.group ? a.group < b.group : a.index < b.index;
  });
  return mine;
}

std::vector<TetRecord> tets_to_parts(const MeshSlab& slab, const std::vector<int>& part,
                                     MPI_Comm comm, int size) {
  const int npe = slab.nodes_per_tet();
  std::vector<std::vector<TetRecord>> out(size);
  for (int64_t i = 0; i < slab.slab_tets(); ++i) {
    TetRecord r{slab.tet_begin + i, slab.tet_volume[i], {}};
    std::copy_n(&slab.tets[npe * i], npe, r.nodes);
    out[part[i]].push_back(r);
  }
  std::vector<TetRecord> mine = all_to_all(out, comm);
  std::sort(mine.begin(), mine.end(),
            [](const TetRecord& a, const TetRecord& b) { return a.id < b.id; });
  return mine;
}

// Orientation of a tetrahedron's corners: det[x1-x0, x2-x0, x3-x0].
double orientation(const double* x0, const double* x1, const double* x2, const double* x3) {
  double a[3], b[3], c[3];
  for (int d = 0; d < 3; ++d) {
    a[d] = x1[d] - x0[d];
    b[d] = x2[d] - x0[d];
    c[d] = x3[d] - x0[d];
  }
  return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
         a[2] * (b[0] * c[1] - b[1] * c[0]);
}

}  // namespace

Distribution distribute_slabs(const MeshSlab& slab, const std::vector<int>& part, MPI_Comm comm) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const int npe = slab.nodes_per_tet(), npf = slab.nodes_per_face();
  const std::string where = slab.file.empty() ? "mesh" : slab.file;
  Distribution d;
  d.rank = rank;
  d.size = size;
  d.order = slab.order;
  d.num_global_tets = slab.num_tets;
  d.groups = slab.groups;

  const std::vector<TetRecord> tets = tets_to_parts(slab, part, comm, size);
  const std::vector<FaceRecord> faces = faces_to_parts(slab, part, comm, size);

  // The nodes of this rank's tetrahedra, asked from their blocks.
  std::vector<int64_t> nodes;
  for (const TetRecord& t : tets) nodes.insert(nodes.end(), t.nodes, t.nodes + npe);
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  std::vector<std::vector<int64_t>> ask(size);
  for (int64_t n : nodes) ask[block_owner(slab.num_nodes, n, size)].push_back(n);
  std::vector<int64_t> asked_by;
  const std::vector<int64_t> asked = all_to_all(ask, comm, &asked_by);

  // At the block: the owner of each node is the lowest rank that asked for it.
  std::vector<int32_t> owner(slab.slab_nodes(), size);
  {
    size_t k = 0;
    for (int r = 0; r < size; ++r)
      for (int64_t i = 0; i < asked_by[r]; ++i, ++k) {
        int32_t& o = owner[asked[k] - slab.node_begin];
        o = std::min(o, r);
      }
  }
  std::string error;
  for (int64_t i = 0; i < slab.slab_nodes() && error.empty(); ++i)
    if (owner[i] == size)
      error =
          where + ": node " + std::to_string(slab.node_begin + i) + " belongs to no tetrahedron";
  throw_together<InputError>(error, comm);

  // Group members to their node's block; then replies: owner, coordinates, groups.
  std::vector<std::vector<NodeInGroup>> members(size);
  {
    int32_t g = 0;
    for (const auto& [name, list] : slab.node_groups) {
      for (int64_t n : list) members[block_owner(slab.num_nodes, n, size)].push_back({n, g});
      ++g;
    }
  }
  std::vector<NodeInGroup> block_members = all_to_all(members, comm);
  std::sort(block_members.begin(), block_members.end(),
            [](const NodeInGroup& a, const NodeInGroup& b) { return a.node < b.node; });
  std::vector<std::vector<NodeReply>> reply(size);
  members.assign(size, {});
  {
    size_t k = 0;
    for (int r = 0; r < size; ++r)
      for (int64_t i = 0; i < asked_by[r]; ++i, ++k) {
        const int64_t n = asked[k], b = n - slab.node_begin;
        reply[r].push_back({owner[b], {slab.x[3 * b], slab.x[3 * b + 1], slab.x[3 * b + 2]}});
        auto it =
            std::lower_bound(block_members.begin(), block_members.end(), n,
                             [](const NodeInGroup& m, int64_t node) { return m.node < node; });
        for (; it != block_members.end() && it->node == n; ++it) members[r].push_back(*it);
      }
  }
  const std::vector<NodeReply> about = all_to_all(reply, comm);  // in the order of `nodes`
  const std::vector<NodeInGroup> my_members = all_to_all(members, comm);
  reply = {};
  members = {};

  // Owned nodes, numbered after those of the lower ranks.
  std::vector<int64_t> owned;
  for (size_t i = 0; i < nodes.size(); ++i)
    if (about[i].owner == rank) owned.push_back(nodes[i]);
  const int64_t nowned = static_cast<int64_t>(owned.size());
  d.owned_offsets.assign(size + 1, 0);
  MPI_Allgather(&nowned, 1, MPI_INT64_T, d.owned_offsets.data() + 1, 1, MPI_INT64_T, comm);
  for (int r = 0; r < size; ++r) d.owned_offsets[r + 1] += d.owned_offsets[r];
  const int64_t first = d.owned_offsets[rank];

  // Ghosts' numbers, from their owners.
  std::vector<std::vector<int64_t>> ghosts_of(size);
  for (size_t i = 0; i < nodes.size(); ++i)
    if (about[i].owner != rank) ghosts_of[about[i].owner].push_back(nodes[i]);
  std::vector<int64_t> ghost_asked_by;
  const std::vector<int64_t> ghost_asked = all_to_all(ghosts_of, comm, &ghost_asked_by);
  std::vector<std::vector<NewId>> ids(size);
  {
    size_t k = 0;
    for (int r = 0; r < size; ++r)
      for (int64_t i = 0; i < ghost_asked_by[r]; ++i, ++k)
        ids[r].push_back({ghost_asked[k], first + position(owned, ghost_asked[k])});
  }
  std::vector<NewId> ghosts = all_to_all(ids, comm);
  std::sort(ghosts.begin(), ghosts.end(),
            [](const NewId& a, const NewId& b) { return a.id < b.id; });

  // Local nodes: owned (their order is the file's), then ghosts by new number.
  for (int64_t i = 0; i < nowned; ++i) {
    d.old_of_local.push_back(owned[i]);
    d.local_nodes.push_back(first + i);
  }
  for (const NewId& g : ghosts) {
    d.old_of_local.push_back(g.node);
    d.local_nodes.push_back(g.id);
  }
  // local index of nodes[i]
  std::vector<int32_t> local_of(nodes.size());
  for (size_t l = 0; l < d.old_of_local.size(); ++l)
    local_of[position(nodes, d.old_of_local[l])] = static_cast<int32_t>(l);
  d.x.resize(3 * d.old_of_local.size());
  for (size_t i = 0; i < nodes.size(); ++i) std::copy_n(about[i].x, 3, &d.x[3 * local_of[i]]);
  auto local = [&](int64_t node) { return local_of[position(nodes, node)]; };

  for (const TetRecord& t : tets) {
    d.local_tets.push_back(t.id);
    d.tet_volume.push_back(t.volume);
    for (int k = 0; k < npe; ++k) d.tet_nodes.push_back(local(t.nodes[k]));
  }
  for (size_t e = 0; e < tets.size() && error.empty(); ++e) {
    const int32_t* c = &d.tet_nodes[npe * e];
    if (!(orientation(&d.x[3 * c[0]], &d.x[3 * c[1]], &d.x[3 * c[2]], &d.x[3 * c[3]]) > 0))
      error = where + ": tetrahedron " + std::to_string(tets[e].id) +
              " is inverted or degenerate (its corners' orientation is not positive)";
  }
  throw_together<InputError>(error, comm);

  std::vector<std::string> surface_names, group_names;
  for (const auto& [name, f] : slab.surfaces) surface_names.push_back(name);
  for (const auto& [name, n] : slab.node_groups) group_names.push_back(name);
  for (const auto& name : surface_names) {
    d.faces[name];
    d.face_index[name];
  }
  for (const FaceRecord& f : faces) {
    auto& list = d.faces[surface_names[f.group]];
    for (int k = 0; k < npf; ++k) list.push_back(local(f.nodes[k]));
    d.face_index[surface_names[f.group]].push_back(f.index);
  }
  for (const auto& name : group_names) d.node_groups[name];
  for (const NodeInGroup& m : my_members)
    d.node_groups[group_names[m.group]].push_back(local(m.node));
  for (auto& [name, list] : d.node_groups) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  return d;
}

}  // namespace hs
