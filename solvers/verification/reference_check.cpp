#include "solvers/verification/reference_check.hpp"

#include "common/deck_reader.hpp"
#include "common/error.hpp"
#include "verification/registry.hpp"

namespace hs {

void check_reference_finite(const Config& config, const ExactSolution& exact,
                            const std::vector<double>& x, MPI_Comm comm) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  std::string reason = non_finite_reference(exact, x);
  // The lowest rank that found one says why, so that every rank throws the same message.
  int first = reason.empty() ? size : rank;
  MPI_Allreduce(MPI_IN_PLACE, &first, 1, MPI_INT, MPI_MIN, comm);
  if (first == size) return;
  int length = static_cast<int>(reason.size());
  MPI_Bcast(&length, 1, MPI_INT, first, comm);
  reason.resize(length);
  MPI_Bcast(reason.data(), length, MPI_CHAR, first, comm);
  std::string given;
  for (const auto& [name, value] : config.exact.parameters)
    given += (given.empty() ? "" : ", ") + name + " = " + format_number(value);
  throw InputError(config.deck_path + ": exact.parameters: exact solution '" +
                   config.exact.type->name + "' with " + given + " cannot be the reference on " +
                   "this mesh: " + reason);
}

}  // namespace hs
