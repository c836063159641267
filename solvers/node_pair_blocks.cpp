#include "solvers/node_pair_blocks.hpp"

#include <algorithm>
#include <stdexcept>

namespace hs {

NodePairBlocks::NodePairBlocks(const std::vector<int32_t>& tet_nodes, int npe, int64_t num_local)
    : npe_(npe) {
  const int64_t ntets = static_cast<int64_t>(tet_nodes.size()) / npe;
  // Tetrahedra around each node (CSR), then each node's neighbours through them.
  std::vector<int64_t> start(num_local + 1, 0);
  for (int32_t n : tet_nodes) ++start[n + 1];
  for (int64_t a = 0; a < num_local; ++a) start[a + 1] += start[a];
  std::vector<int64_t> around(tet_nodes.size()), next(start.begin(), start.end() - 1);
  for (int64_t e = 0; e < ntets; ++e)
    for (int k = 0; k < npe; ++k) around[next[tet_nodes[npe * e + k]]++] = e;
  offsets_.assign(num_local + 1, 0);
  std::vector<int32_t> row;
  for (int64_t a = 0; a < num_local; ++a) {
    row.clear();
    for (int64_t i = start[a]; i < start[a + 1]; ++i)
      for (int k = 0; k < npe; ++k) row.push_back(tet_nodes[npe * around[i] + k]);
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
    columns_.insert(columns_.end(), row.begin(), row.end());
    offsets_[a + 1] = static_cast<int64_t>(columns_.size());
  }
  tet_slots_.resize(static_cast<size_t>(ntets) * npe * npe);
  for (int64_t e = 0; e < ntets; ++e)
    for (int i = 0; i < npe; ++i)
      for (int j = 0; j < npe; ++j)
        tet_slots_[(e * npe + i) * npe + j] = slot(tet_nodes[npe * e + i], tet_nodes[npe * e + j]);
}

int64_t NodePairBlocks::slot(int32_t a, int32_t b) const {
  const auto first = columns_.begin() + offsets_[a], last = columns_.begin() + offsets_[a + 1];
  const auto it = std::lower_bound(first, last, b);
  return it != last && *it == b ? it - columns_.begin() : -1;
}

void NodePairBlocks::add_tet(int64_t e, const double* K, double* values) const {
  const int n = 3 * npe_;
  const int64_t* slots = &tet_slots_[e * npe_ * npe_];
  for (int i = 0; i < npe_; ++i)
    for (int j = 0; j < npe_; ++j) {
      double* block = values + 9 * slots[i * npe_ + j];
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) block[3 * r + c] += K[(3 * i + r) * n + 3 * j + c];
    }
}

void NodePairBlocks::add_nodes(const int32_t* nodes, int n, const double* K, double* values) const {
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const int64_t s = slot(nodes[i], nodes[j]);
      if (s < 0) throw std::logic_error("NodePairBlocks: the nodes share no tetrahedron");
      double* block = values + 9 * s;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) block[3 * r + c] += K[(3 * i + r) * 3 * n + 3 * j + c];
    }
}

}  // namespace hs
