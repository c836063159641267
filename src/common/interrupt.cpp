#include "common/interrupt.hpp"

#include <signal.h>

namespace hs {
namespace {

volatile sig_atomic_t received = 0;

// Async-signal-safe: a store and sigaction only. Without SA_RESTART, a blocking read of the
// interactive mode's targets returns (EINTR) instead of waiting for a line that may never
// come. Linux hands a signal sent to the process to its main thread unless that thread blocks
// it, so the main thread's read is the one interrupted.
void on_signal(int signal) {
  if (received == 0) received = signal;
  struct sigaction fallback {};
  fallback.sa_handler = SIG_DFL;
  sigemptyset(&fallback.sa_mask);
  sigaction(SIGTERM, &fallback, nullptr);
  sigaction(SIGINT, &fallback, nullptr);
}

}  // namespace

Interrupted::Interrupted(int signal)
    : SolveError("interrupted by " + signal_name(signal)), signal(signal) {}

void install_interrupt_handlers() {
  struct sigaction action {};
  action.sa_handler = on_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = 0;
  sigaction(SIGTERM, &action, nullptr);
  sigaction(SIGINT, &action, nullptr);
}

int interrupt_signal() { return received; }

int interrupt_requested(MPI_Comm comm) {
  int signal = received;
  MPI_Allreduce(MPI_IN_PLACE, &signal, 1, MPI_INT, MPI_MAX, comm);
  return signal;
}

void stop_if_interrupted(MPI_Comm comm) {
  if (const int signal = interrupt_requested(comm)) throw Interrupted(signal);
}

std::string signal_name(int signal) {
  if (signal == SIGTERM) return "SIGTERM";
  if (signal == SIGINT) return "SIGINT";
  return "signal " + std::to_string(signal);
}

}  // namespace hs
