#include "solvers/reduced/whole_body.hpp"

#include "deck/exact_section.hpp"
#include "solvers/distributed_mesh.hpp"
#include "solvers/run_setup.hpp"

namespace hs {

WholeBody::WholeBody(const Config& config, const std::vector<Constraint::State>& states)
    : dist(load_distributed_mesh(config.mesh, MPI_COMM_SELF, nullptr, config.solver)),
      exact(make_exact_solution(config)),
      problem(make_problem(config, dist, MPI_COMM_SELF, exact.get())),
      constraints(std::make_unique<ConstraintSet>(config, *problem)),
      effectors(std::make_unique<Effectors>(config, *problem)) {
  constraints->restore(states);
}

std::vector<Eigen::VectorXd> WholeBody::local_order(
    const std::vector<Eigen::VectorXd>& in_mesh_order) const {
  std::vector<Eigen::VectorXd> out;
  for (const Eigen::VectorXd& v : in_mesh_order) {
    Eigen::VectorXd local(3 * dist.num_local());
    for (int64_t n = 0; n < dist.num_local(); ++n)
      local.segment<3>(3 * n) = v.segment<3>(3 * dist.old_of_local[n]);
    out.push_back(local);
  }
  return out;
}

std::vector<Eigen::VectorXd> gather_in_mesh_order(const Problem& problem,
                                                  const std::vector<Eigen::VectorXd>& owned) {
  const Distribution& dist = problem.distribution();
  const MPI_Comm comm = problem.comm();
  int size = 1, rank = 0;
  MPI_Comm_size(comm, &size);
  MPI_Comm_rank(comm, &rank);
  const int mine = static_cast<int>(dist.num_owned());
  std::vector<int> counts(size), displs(size, 0);
  MPI_Gather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm);
  for (int r = 1; r < size; ++r) displs[r] = displs[r - 1] + counts[r - 1];
  const int total = displs[size - 1] + counts[size - 1];
  std::vector<int64_t> nodes(rank == 0 ? total : 0);
  MPI_Gatherv(dist.old_of_local.data(), mine, MPI_INT64_T, nodes.data(), counts.data(),
              displs.data(), MPI_INT64_T, 0, comm);
  for (int r = 0; r < size; ++r) {
    counts[r] *= 3;
    displs[r] *= 3;
  }
  std::vector<Eigen::VectorXd> out;
  std::vector<double> values(rank == 0 ? 3 * total : 0);
  for (const Eigen::VectorXd& v : owned) {
    MPI_Gatherv(v.data(), 3 * mine, MPI_DOUBLE, values.data(), counts.data(), displs.data(),
                MPI_DOUBLE, 0, comm);
    if (rank != 0) continue;
    Eigen::VectorXd whole(3 * dist.num_global());
    for (int i = 0; i < total; ++i)
      whole.segment<3>(3 * nodes[i]) = Eigen::Map<const Eigen::Vector3d>(&values[3 * i]);
    out.push_back(whole);
  }
  return out;
}

}  // namespace hs
