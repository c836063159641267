// Personalised all-to-all of plain records, and an error that every rank raises together.
// The parallel mesh construction moves everything with all_to_all(): each rank hands a list of
// records to each other rank and receives the lists addressed to it.
#pragma once

#include <mpi.h>

#include <climits>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "common/error.hpp"

namespace hs {

// Sends send[r] to rank r (send has one list per rank) and returns the records received,
// in the order of the sending ranks; from[r], if given, gets how many came from rank r.
template <class T>
std::vector<T> all_to_all(const std::vector<std::vector<T>>& send, MPI_Comm comm,
                          std::vector<int64_t>* from = nullptr) {
  static_assert(std::is_trivially_copyable<T>::value, "all_to_all moves plain records");
  int size = 1;
  MPI_Comm_size(comm, &size);
  if (static_cast<int>(send.size()) != size)
    throw std::logic_error("all_to_all: one list per rank is needed");
  std::vector<int> scount(size), sdispl(size), rcount(size), rdispl(size);
  std::vector<char> sbuf;
  int64_t total = 0;
  for (int r = 0; r < size; ++r) total += static_cast<int64_t>(send[r].size() * sizeof(T));
  if (total > INT_MAX)
    throw std::runtime_error("all_to_all: more than 2 GiB to send from one rank (use more ranks)");
  sbuf.reserve(total);
  for (int r = 0; r < size; ++r) {
    sdispl[r] = static_cast<int>(sbuf.size());
    scount[r] = static_cast<int>(send[r].size() * sizeof(T));
    const char* p = reinterpret_cast<const char*>(send[r].data());
    sbuf.insert(sbuf.end(), p, p + scount[r]);
  }
  MPI_Alltoall(scount.data(), 1, MPI_INT, rcount.data(), 1, MPI_INT, comm);
  int64_t received = 0;
  for (int r = 0; r < size; ++r) {
    rdispl[r] = static_cast<int>(received);
    received += rcount[r];
  }
  if (received > INT_MAX)
    throw std::runtime_error("all_to_all: more than 2 GiB to receive on one rank (use more ranks)");
  std::vector<T> out(received / sizeof(T));
  MPI_Alltoallv(sbuf.data(), scount.data(), sdispl.data(), MPI_BYTE, out.data(), rcount.data(),
                rdispl.data(), MPI_BYTE, comm);
  if (from) {
    from->resize(size);
    for (int r = 0; r < size; ++r) (*from)[r] = rcount[r] / static_cast<int64_t>(sizeof(T));
  }
  return out;
}

// The first item of the block that rank r of `size` holds when n items are split in
// contiguous blocks as evenly as possible, and the rank whose block holds item i.
inline int64_t block_begin(int64_t n, int rank, int size) { return n * rank / size; }
inline int block_owner(int64_t n, int64_t i, int size) {
  return static_cast<int>(((i + 1) * size + n - 1) / n - 1);
}

// Collective: `text` of rank `root` on every rank.
inline void broadcast_string(std::string& text, int root, MPI_Comm comm) {
  int n = static_cast<int>(text.size());
  MPI_Bcast(&n, 1, MPI_INT, root, comm);
  text.resize(n);
  MPI_Bcast(text.data(), n, MPI_CHAR, root, comm);
}

// Collective: when any rank has a non-empty `error`, every rank throws E with the message of
// the lowest such rank; otherwise returns.
template <class E>
void throw_together(const std::string& error, MPI_Comm comm) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  int first = error.empty() ? size : rank;
  MPI_Allreduce(MPI_IN_PLACE, &first, 1, MPI_INT, MPI_MIN, comm);
  if (first == size) return;
  std::string message = error;
  broadcast_string(message, first, comm);
  throw E(message);
}

// Collective: rank 0 runs `work`; what it throws is thrown on every rank with its message, an
// InputError as InputError, a SolveError as SolveError, anything else as std::runtime_error.
template <class F>
void on_rank_zero(MPI_Comm comm, F&& work) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  std::string input_error, solve_error, other_error;
  if (rank == 0) {
    try {
      work();
    } catch (const InputError& e) {
      input_error = e.what();
    } catch (const SolveError& e) {
      solve_error = e.what();
    } catch (const std::exception& e) {
      other_error = e.what();
    }
  }
  throw_together<InputError>(input_error, comm);
  throw_together<SolveError>(solve_error, comm);
  throw_together<std::runtime_error>(other_error, comm);
}

}  // namespace hs
