// The collective check after a write: a write that fails on one rank must stop every rank at
// the same point. A rank that threw alone would leave the others waiting forever in their
// next collective call (an HDF5 write, the closing of the file in a destructor), with nothing
// printed.
#pragma once

#include <mpi.h>

#include <stdexcept>
#include <string>

#include "common/error.hpp"
#include "common/exchange.hpp"

namespace hs {

// Runs `write` where `here` is true (rank 0 alone, for the files it writes alone; every rank
// for a collective write). If it threw std::runtime_error (a file that cannot be written:
// the message names it and the reason) on any rank, every rank throws SolveError with the
// message of the lowest such rank: a run that fails mid-way (exit status 3), which keeps its
// converged steps. With MPI_COMM_NULL (serial) the error is thrown at once.
template <class F>
void write_together(MPI_Comm comm, bool here, F&& write) {
  std::string error;
  if (here) {
    try {
      write();
    } catch (const std::runtime_error& e) {
      error = e.what();
    }
  }
  if (comm != MPI_COMM_NULL)
    throw_together<SolveError>(error, comm);
  else if (!error.empty())
    throw SolveError(error);
}

}  // namespace hs
