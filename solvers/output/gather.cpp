#include "solvers/output/gather.hpp"

namespace hs {

std::vector<double> gather_nodal(const Problem& problem, Vec v) {
  const Distribution& dist = problem.distribution();
  const Mesh& mesh = problem.mesh();
  const MPI_Comm comm = problem.comm();
  const int nowned = static_cast<int>(dist.num_owned());
  const PetscScalar* a;
  HS_PETSC(VecGetArrayRead(v, &a));
  std::vector<double> mine(a, a + 3 * nowned);
  HS_PETSC(VecRestoreArrayRead(v, &a));
  std::vector<double> all;
  std::vector<int> counts(dist.size), displs(dist.size);
  for (int r = 0; r < dist.size; ++r) {
    counts[r] = static_cast<int>(3 * (dist.owned_offsets[r + 1] - dist.owned_offsets[r]));
    displs[r] = static_cast<int>(3 * dist.owned_offsets[r]);
  }
  if (dist.rank == 0) all.resize(3 * dist.num_global());
  MPI_Gatherv(mine.data(), 3 * nowned, MPI_DOUBLE, all.data(), counts.data(), displs.data(),
              MPI_DOUBLE, 0, comm);
  if (dist.rank != 0) return {};
  // New (rank-contiguous) numbering to mesh numbering.
  std::vector<double> out(all.size());
  for (int64_t old = 0; old < mesh.num_nodes(); ++old)
    for (int d = 0; d < 3; ++d) out[3 * old + d] = all[3 * dist.new_of_old[old] + d];
  return out;
}

std::vector<double> gather_elemental(const Problem& problem, const std::vector<double>& local) {
  const Distribution& dist = problem.distribution();
  const Mesh& mesh = problem.mesh();
  const MPI_Comm comm = problem.comm();
  const int n = static_cast<int>(local.size());
  std::vector<int> counts(dist.size), displs(dist.size);
  MPI_Gather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm);
  std::vector<long long> ids(dist.local_tets.begin(), dist.local_tets.end());
  int total = 0;
  if (dist.rank == 0)
    for (int r = 0; r < dist.size; ++r) {
      displs[r] = total;
      total += counts[r];
    }
  std::vector<double> values(total);
  std::vector<long long> all_ids(total);
  MPI_Gatherv(local.data(), n, MPI_DOUBLE, values.data(), counts.data(), displs.data(), MPI_DOUBLE,
              0, comm);
  MPI_Gatherv(ids.data(), n, MPI_LONG_LONG, all_ids.data(), counts.data(), displs.data(),
              MPI_LONG_LONG, 0, comm);
  if (dist.rank != 0) return {};
  std::vector<double> out(mesh.num_tets(), 0.0);
  for (int i = 0; i < total; ++i) out[all_ids[i]] = values[i];
  return out;
}

}  // namespace hs
