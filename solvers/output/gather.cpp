#include "solvers/output/gather.hpp"

namespace hs {
namespace {

// Rank 0 gets every rank's (mesh number, width values) rows and places them by number.
std::vector<double> gather_rows(const Problem& problem, const std::vector<int64_t>& ids,
                                const double* values, int width, int64_t total) {
  const MPI_Comm comm = problem.comm();
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const int n = static_cast<int>(ids.size());
  std::vector<int> counts(size), displs(size);
  MPI_Gather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm);
  int all = 0;
  for (int r = 0; r < size; ++r) {
    displs[r] = all;
    all += counts[r];
  }
  std::vector<long long> all_ids(all);
  std::vector<long long> mine(ids.begin(), ids.end());
  MPI_Gatherv(mine.data(), n, MPI_LONG_LONG, all_ids.data(), counts.data(), displs.data(),
              MPI_LONG_LONG, 0, comm);
  MPI_Datatype row;
  MPI_Type_contiguous(width, MPI_DOUBLE, &row);
  MPI_Type_commit(&row);
  std::vector<double> all_values(static_cast<size_t>(all) * width);
  MPI_Gatherv(values, n, row, all_values.data(), counts.data(), displs.data(), row, 0, comm);
  MPI_Type_free(&row);
  if (rank != 0) return {};
  std::vector<double> out(total * width, 0.0);
  for (int i = 0; i < all; ++i)
    for (int k = 0; k < width; ++k) out[all_ids[i] * width + k] = all_values[i * width + k];
  return out;
}

}  // namespace

std::vector<double> gather_nodal(const Problem& problem, Vec v) {
  const Distribution& dist = problem.distribution();
  const std::vector<int64_t> ids(dist.old_of_local.begin(),
                                 dist.old_of_local.begin() + dist.num_owned());
  const PetscScalar* a;
  HS_PETSC(VecGetArrayRead(v, &a));
  std::vector<double> out = gather_rows(problem, ids, a, 3, dist.num_global());
  HS_PETSC(VecRestoreArrayRead(v, &a));
  return out;
}

}  // namespace hs
