// SIGTERM and SIGINT (a cluster's wall-time limit, Ctrl-C) stop a run at the next step
// boundary instead of killing it, so that the steps that converged are kept (docs/output.md,
// docs/reliability.md). The handler only records the signal; the run asks, at each step
// boundary and on every rank together, whether any rank got one.
#pragma once

#include <mpi.h>

#include <string>

#include "common/error.hpp"

namespace hs {

// The run stopped on a signal: what() is "interrupted by SIGTERM" (or SIGINT).
struct Interrupted : SolveError {
  explicit Interrupted(int signal);
  int signal;
};

// Installs the handlers of SIGTERM and SIGINT. The first of them sets the flag and puts both
// back to their default action, so that a second one ends the process at once. Installed
// after PetscInitialize, which has a SIGTERM handler of its own.
void install_interrupt_handlers();

// The signal this process received (0 if none).
int interrupt_signal();

// Collective: the signal any rank received (the largest number if they differ), or 0.
int interrupt_requested(MPI_Comm comm);

// Collective: throws Interrupted on every rank when any rank received a signal.
void stop_if_interrupted(MPI_Comm comm);

// "SIGTERM", "SIGINT", or "signal N".
std::string signal_name(int signal);

}  // namespace hs
