#include "solvers/gathered_surface.hpp"

#include <algorithm>

namespace hs {
namespace {

struct FaceRecord {
  int64_t index;  // in the whole group
  int64_t mesh[6], global[6];
  double x[18];
};

}  // namespace

GatheredSurface gather_surface(const Distribution& dist, const std::string& group, int root,
                               MPI_Comm comm) {
  const int npf = dist.nodes_per_face();
  std::vector<FaceRecord> mine;
  const auto faces = dist.faces.find(group);
  if (faces != dist.faces.end()) {
    const std::vector<int64_t>& index = dist.face_index.at(group);
    for (size_t f = 0; f < index.size(); ++f) {
      FaceRecord r{index[f], {}, {}, {}};
      for (int a = 0; a < npf; ++a) {
        const int32_t l = faces->second[npf * f + a];
        r.mesh[a] = dist.old_of_local[l];
        r.global[a] = dist.local_nodes[l];
        for (int d = 0; d < 3; ++d) r.x[3 * a + d] = dist.x[3 * l + d];
      }
      mine.push_back(r);
    }
  }
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const int bytes = static_cast<int>(mine.size() * sizeof(FaceRecord));
  std::vector<int> counts(size), displs(size);
  if (root < 0)
    MPI_Allgather(&bytes, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
  else
    MPI_Gather(&bytes, 1, MPI_INT, counts.data(), 1, MPI_INT, root, comm);
  int total = 0;
  for (int r = 0; r < size; ++r) {
    displs[r] = total;
    total += counts[r];
  }
  std::vector<FaceRecord> all(total / sizeof(FaceRecord));
  if (root < 0)
    MPI_Allgatherv(mine.data(), bytes, MPI_BYTE, all.data(), counts.data(), displs.data(), MPI_BYTE,
                   comm);
  else
    MPI_Gatherv(mine.data(), bytes, MPI_BYTE, all.data(), counts.data(), displs.data(), MPI_BYTE,
                root, comm);
  GatheredSurface s;
  s.nodes_per_face = npf;
  if (root >= 0 && rank != root) return s;
  std::sort(all.begin(), all.end(),
            [](const FaceRecord& a, const FaceRecord& b) { return a.index < b.index; });
  std::vector<std::pair<int64_t, size_t>> seen;  // mesh number, where (face * npf + a)
  for (size_t f = 0; f < all.size(); ++f)
    for (int a = 0; a < npf; ++a) seen.push_back({all[f].mesh[a], f * npf + a});
  std::sort(seen.begin(), seen.end());
  s.faces.resize(all.size() * npf);
  for (size_t k = 0; k < seen.size(); ++k) {
    const auto [node, at] = seen[k];
    if (s.mesh_nodes.empty() || s.mesh_nodes.back() != node) {
      const FaceRecord& r = all[at / npf];
      const int a = static_cast<int>(at % npf);
      s.mesh_nodes.push_back(node);
      s.global_nodes.push_back(r.global[a]);
      s.x.insert(s.x.end(), r.x + 3 * a, r.x + 3 * a + 3);
    }
    s.faces[at] = static_cast<int>(s.mesh_nodes.size() - 1);
  }
  return s;
}

}  // namespace hs
