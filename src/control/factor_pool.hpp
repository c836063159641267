// Threads that make Cholesky factorizations while the control loop steps on
// (docs/control.md, "Factorizations in the background"). The loop hands over a copy of a
// tangent (a CsrMatrix, tagged with the step whose state it is) whenever a thread is free,
// and collects the finished factorizations, or why one failed, at its step boundaries. The
// threads touch neither PETSc nor MPI: each has its own CHOLMOD analysis and workspace.
#pragma once

#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "control/sparse_cholesky.hpp"

namespace hs {

struct FactorResult {
  int state = 0;                           // the step whose tangent it is
  std::unique_ptr<CholeskyFactor> factor;  // null when it failed
  std::string error;                       // why it failed
  double seconds = 0;                      // the factorization's time (its thread's clock)
};

class FactorPool {
 public:
  explicit FactorPool(int threads);
  ~FactorPool();  // waits for the factorizations in flight, then ends the threads
  FactorPool(const FactorPool&) = delete;
  FactorPool& operator=(const FactorPool&) = delete;

  int threads() const { return static_cast<int>(workers_.size()); }
  // Whether a thread is free for a new tangent.
  bool idle() const;
  // Queues A (moved) when a thread is free; returns false (A untouched) when none is.
  bool submit(CsrMatrix& A, int state);
  // The results finished since the last call, oldest first.
  std::vector<FactorResult> take_finished();
  // Blocks until nothing is in flight (for tests and the end of a run).
  void wait_idle();

 private:
  struct Job {
    CsrMatrix matrix;
    int state = 0;
  };
  void work();

  mutable std::mutex mutex_;
  std::condition_variable job_ready_, job_done_;
  std::deque<Job> jobs_;
  std::vector<FactorResult> finished_;
  int in_flight_ = 0;  // queued or being factored
  bool stopping_ = false;
  std::vector<std::thread> workers_;
};

}  // namespace hs
