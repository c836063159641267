// distribute: the pieces of all ranks, computed on one process, must tile the mesh (every tet
// once, every node owned once, faces and groups split without loss) in the documented layout.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <set>

#include "common/error.hpp"
#include "mesh/distribution.hpp"
#include "mesh_test_util.hpp"

namespace hs::test {
namespace {

std::vector<int64_t> tet_face(const Mesh& m, const std::vector<int64_t>& faces, size_t f) {
  const int npf = m.nodes_per_face();
  return std::vector<int64_t>(faces.begin() + f * npf, faces.begin() + (f + 1) * npf);
}

// Slices along the mesh's longest extent, balanced by count: any partition will do here.
std::vector<int> slices(const Mesh& m, int size) {
  const int npe = m.nodes_per_tet();
  std::vector<std::pair<double, int64_t>> order;
  for (int64_t t = 0; t < m.num_tets(); ++t)
    order.push_back({m.x[3 * m.tets[npe * t]] + 1e-3 * m.x[3 * m.tets[npe * t] + 1], t});
  std::sort(order.begin(), order.end());
  std::vector<int> part(m.num_tets());
  for (size_t k = 0; k < order.size(); ++k)
    part[order[k].second] = static_cast<int>(k * size / order.size());
  return part;
}

// All the checks of one mesh split `size` ways.
void check_distribution(const Mesh& m, int size) {
  const std::vector<int> part = slices(m, size);

  const int npe = m.nodes_per_tet();
  // The documented owner of a node: the lowest part among its tetrahedra.
  std::vector<int> owner(m.num_nodes(), size);
  for (int64_t t = 0; t < m.num_tets(); ++t)
    for (int k = 0; k < npe; ++k)
      owner[m.tets[t * npe + k]] = std::min(owner[m.tets[t * npe + k]], part[t]);

  std::vector<Distribution> d;
  for (int r = 0; r < size; ++r) d.push_back(distribute(m, part, r, size));
  const auto& offsets = d[0].owned_offsets;
  std::vector<int64_t> new_of_old(m.num_nodes(), -1);  // from the owners' pieces
  for (const Distribution& dr : d)
    for (int64_t i = 0; i < dr.num_owned(); ++i) new_of_old[dr.old_of_local[i]] = dr.local_nodes[i];
  ASSERT_EQ(static_cast<int>(offsets.size()), size + 1);
  EXPECT_EQ(offsets.front(), 0);
  EXPECT_EQ(offsets.back(), m.num_nodes());

  // The renumbering is a permutation, contiguous per owner, in mesh order inside each owner.
  std::vector<int64_t> sorted = new_of_old;
  std::sort(sorted.begin(), sorted.end());
  std::vector<int64_t> iota(m.num_nodes());
  std::iota(iota.begin(), iota.end(), 0);
  EXPECT_EQ(sorted, iota);
  std::vector<int64_t> last(size, -1);
  for (int64_t n = 0; n < m.num_nodes(); ++n) {
    const int o = owner[n];
    EXPECT_GE(new_of_old[n], offsets[o]);
    EXPECT_LT(new_of_old[n], offsets[o + 1]);
    EXPECT_GT(new_of_old[n], last[o]);
    last[o] = new_of_old[n];
  }

  std::vector<int> tet_seen(m.num_tets(), 0);
  std::map<std::string, std::multiset<std::vector<int64_t>>> faces_seen;
  std::map<std::string, std::set<int64_t>> groups_seen;
  for (int r = 0; r < size; ++r) {
    const Distribution& dr = d[r];
    EXPECT_EQ(dr.owned_offsets, offsets);
    for (int64_t i = 0; i < dr.num_local(); ++i)
      for (int k = 0; k < 3; ++k) EXPECT_EQ(dr.x[3 * i + k], m.x[3 * dr.old_of_local[i] + k]);
    EXPECT_EQ(dr.num_global(), m.num_nodes());
    // Owned nodes first, the whole owned range in order; then the ghosts, ascending.
    const int64_t nown = dr.num_owned();
    ASSERT_GE(dr.num_local(), nown);
    for (int64_t i = 0; i < nown; ++i) EXPECT_EQ(dr.local_nodes[i], offsets[r] + i);
    for (int64_t i = nown + 1; i < dr.num_local(); ++i)
      EXPECT_LT(dr.local_nodes[i - 1], dr.local_nodes[i]);
    for (int64_t i = 0; i < dr.num_local(); ++i)
      EXPECT_EQ(new_of_old[dr.old_of_local[i]], dr.local_nodes[i]);
    // Ghosts are exactly the non-owned nodes of the local tetrahedra.
    std::set<int64_t> expected_ghosts;
    for (int64_t t = 0; t < m.num_tets(); ++t)
      if (part[t] == r)
        for (int k = 0; k < npe; ++k)
          if (owner[m.tets[t * npe + k]] != r) expected_ghosts.insert(m.tets[t * npe + k]);
    const std::set<int64_t> ghosts(dr.old_of_local.begin() + nown, dr.old_of_local.end());
    EXPECT_EQ(ghosts, expected_ghosts);
    // Local tetrahedra: this part's, with their nodes in local indices.
    ASSERT_EQ(dr.tet_nodes.size(), dr.local_tets.size() * npe);
    for (size_t e = 0; e < dr.local_tets.size(); ++e) {
      const int64_t t = dr.local_tets[e];
      EXPECT_EQ(part[t], r);
      ++tet_seen[t];
      for (int k = 0; k < npe; ++k)
        EXPECT_EQ(dr.old_of_local[dr.tet_nodes[e * npe + k]], m.tets[t * npe + k]);
    }
    for (const auto& [g, faces] : dr.faces)
      for (size_t f = 0; f < faces.size() / m.nodes_per_face(); ++f) {
        std::vector<int64_t> old;
        for (int k = 0; k < m.nodes_per_face(); ++k)
          old.push_back(dr.old_of_local[faces[f * m.nodes_per_face() + k]]);
        faces_seen[g].insert(old);
      }
    for (const auto& [g, nodes] : dr.node_groups) {
      const std::set<int64_t> group(m.node_groups.at(g).begin(), m.node_groups.at(g).end());
      std::set<int64_t> local_members;
      for (int64_t i = 0; i < dr.num_local(); ++i)
        if (group.count(dr.old_of_local[i])) local_members.insert(i);
      EXPECT_EQ(std::set<int64_t>(nodes.begin(), nodes.end()), local_members) << g;
      EXPECT_TRUE(std::is_sorted(nodes.begin(), nodes.end()));
      for (int32_t i : nodes) groups_seen[g].insert(dr.old_of_local[i]);
    }
  }
  for (int64_t t = 0; t < m.num_tets(); ++t) EXPECT_EQ(tet_seen[t], 1) << "tet " << t;
  // Union over ranks = the whole group; each face exactly once.
  for (const auto& [g, faces] : m.surfaces) {
    std::multiset<std::vector<int64_t>> all;
    for (size_t f = 0; f < faces.size() / m.nodes_per_face(); ++f)
      all.insert(tet_face(m, faces, f));
    EXPECT_EQ(faces_seen[g], all) << g;
  }
  for (const auto& [g, nodes] : m.node_groups)
    EXPECT_EQ(std::vector<int64_t>(groups_seen[g].begin(), groups_seen[g].end()), nodes) << g;
}

TEST(Distribution, SphereP1OnOneToFourRanks) {
  const Mesh m = load_geo("lame_sphere.geo", {{"h", 0.3}}, 1);
  for (int size = 1; size <= 4; ++size) {
    SCOPED_TRACE("size " + std::to_string(size));
    check_distribution(m, size);
  }
}

TEST(Distribution, BlockP2OnOneToFourRanks) {
  const Mesh m = load_geo("block.geo", {{"h", 0.25}}, 2);
  for (int size = 1; size <= 4; ++size) {
    SCOPED_TRACE("size " + std::to_string(size));
    check_distribution(m, size);
  }
}

TEST(Distribution, OnePartIsTheWholeMeshInItsOwnOrder) {
  const Mesh m = load_geo("block.geo", {{"h", 0.5}}, 1);
  const Distribution d = distribute(m, std::vector<int>(m.num_tets(), 0), 0, 1);
  std::vector<int64_t> iota(m.num_nodes());
  std::iota(iota.begin(), iota.end(), 0);
  EXPECT_EQ(d.local_nodes, iota);
  EXPECT_EQ(d.old_of_local, iota);
  EXPECT_EQ(d.num_owned(), m.num_nodes());
  EXPECT_EQ(std::vector<int64_t>(d.tet_nodes.begin(), d.tet_nodes.end()), m.tets);
}

}  // namespace
}  // namespace hs::test
