// distribute: one rank's piece of a whole mesh, computed without communication (the
// reference of the parallel distribute_slabs).
//
// Node ownership: a node belongs to the lowest part among the tetrahedra that contain it.
// Any rule that every rank evaluates alike would do; this one needs only the partition, and
// every owned node of a rank is a node of one of its own tetrahedra (so a rank never owns a
// node it does not assemble).
// Numbering: rank r owns the new ids [off[r], off[r+1]), nodes taken in their mesh order,
// so the renumbering is deterministic and PETSc's contiguous layout follows directly.
#include "mesh/distribution.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

namespace hs {
namespace {

// The owning part of every node (see above).
std::vector<int> node_owners(const Mesh& mesh, const std::vector<int>& tet_part, int size) {
  const int npe = mesh.nodes_per_tet();
  std::vector<int> owner(mesh.num_nodes(), size);  // size = "in no tetrahedron yet"
  for (int64_t t = 0; t < mesh.num_tets(); ++t)
    for (int k = 0; k < npe; ++k) {
      int& o = owner[mesh.tets[t * npe + k]];
      o = std::min(o, tet_part[t]);
    }
  for (int64_t n = 0; n < mesh.num_nodes(); ++n)
    if (owner[n] == size)
      throw std::invalid_argument("distribute: node " + std::to_string(n) +
                                  " belongs to no tetrahedron");
  return owner;
}

}  // namespace

Distribution distribute(const Mesh& mesh, const std::vector<int>& tet_part, int rank, int size) {
  const int64_t nnodes = mesh.num_nodes(), ntets = mesh.num_tets();
  const int npe = mesh.nodes_per_tet();
  if (size < 1 || rank < 0 || rank >= size)
    throw std::invalid_argument("distribute: rank " + std::to_string(rank) + " of " +
                                std::to_string(size));
  if (static_cast<int64_t>(tet_part.size()) != ntets)
    throw std::invalid_argument("distribute: the partition has a wrong size");
  for (int p : tet_part)
    if (p < 0 || p >= size) throw std::invalid_argument("distribute: part out of range");

  Distribution d;
  d.rank = rank;
  d.size = size;
  d.order = mesh.order;
  d.num_global_tets = ntets;
  d.groups = groups_of(mesh);
  const std::vector<int> owner = node_owners(mesh, tet_part, size);

  // Contiguous new numbering per owner, in mesh order within each owner.
  d.owned_offsets.assign(size + 1, 0);
  for (int o : owner) ++d.owned_offsets[o + 1];
  for (int r = 0; r < size; ++r) d.owned_offsets[r + 1] += d.owned_offsets[r];
  std::vector<int64_t> next(d.owned_offsets.begin(), d.owned_offsets.end() - 1);
  std::vector<int64_t> new_of_old(nnodes);
  for (int64_t n = 0; n < nnodes; ++n) new_of_old[n] = next[owner[n]]++;

  // Local nodes: owned ones (in new-id order, which is their mesh order), then ghosts.
  for (int64_t n = 0; n < nnodes; ++n)
    if (owner[n] == rank) d.old_of_local.push_back(n);
  std::vector<int64_t> ghosts;
  for (int64_t t = 0; t < ntets; ++t) {
    if (tet_part[t] != rank) continue;
    d.local_tets.push_back(t);
    d.tet_volume.push_back(mesh.tet_volume[t]);
    for (int k = 0; k < npe; ++k) {
      const int64_t n = mesh.tets[t * npe + k];
      if (owner[n] != rank) ghosts.push_back(n);
    }
  }
  std::sort(ghosts.begin(), ghosts.end(),
            [&](int64_t a, int64_t b) { return new_of_old[a] < new_of_old[b]; });
  ghosts.erase(std::unique(ghosts.begin(), ghosts.end()), ghosts.end());
  d.old_of_local.insert(d.old_of_local.end(), ghosts.begin(), ghosts.end());
  if (d.old_of_local.size() > static_cast<size_t>(std::numeric_limits<int32_t>::max()))
    throw std::invalid_argument("distribute: too many local nodes for 32-bit local indices");

  std::vector<int32_t> local_of_old(nnodes, -1);
  for (size_t i = 0; i < d.old_of_local.size(); ++i) {
    local_of_old[d.old_of_local[i]] = static_cast<int32_t>(i);
    d.local_nodes.push_back(new_of_old[d.old_of_local[i]]);
    for (int k = 0; k < 3; ++k) d.x.push_back(mesh.x[3 * d.old_of_local[i] + k]);
  }

  d.tet_nodes.reserve(d.local_tets.size() * npe);
  for (int64_t t : d.local_tets)
    for (int k = 0; k < npe; ++k) d.tet_nodes.push_back(local_of_old[mesh.tets[t * npe + k]]);

  // Faces go with the tetrahedron they bound, so all their nodes are local.
  const int npf = mesh.nodes_per_face();
  for (const auto& [name, faces] : mesh.surfaces) {
    const std::vector<int64_t>& face_tets = mesh.surface_tets.at(name);
    std::vector<int32_t>& local = d.faces[name];
    std::vector<int64_t>& index = d.face_index[name];
    for (size_t f = 0; f < face_tets.size(); ++f) {
      if (tet_part[face_tets[f]] != rank) continue;
      index.push_back(static_cast<int64_t>(f));
      for (int k = 0; k < npf; ++k) local.push_back(local_of_old[faces[f * npf + k]]);
    }
  }
  // Node groups: their local members, in local order.
  for (const auto& [name, nodes] : mesh.node_groups) {
    std::vector<int32_t>& local = d.node_groups[name];
    for (int64_t n : nodes)
      if (local_of_old[n] >= 0) local.push_back(local_of_old[n]);
    std::sort(local.begin(), local.end());
  }
  return d;
}

}  // namespace hs
