// A sequential sparse Cholesky factorization (CHOLMOD's supernodal L L^T) of a symmetric
// matrix given in CSR, made and used without PETSc, so that a thread of its own can make it
// while the control loop goes on (docs/control.md, "Factorizations in the background").
// Only the upper triangle of each row's columns at or before the diagonal is read: the
// matrix is taken as symmetric.
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace hs {

// Compressed sparse rows, 0-based, columns sorted within each row.
struct CsrMatrix {
  int n = 0;
  std::vector<int> row_start;  // n + 1
  std::vector<int> column;
  std::vector<double> value;
};

class CholeskyFactor;

// The symbolic analysis of one pattern (fill-reducing ordering, supernodes), reused by every
// factorization of matrices with that pattern. Not shared between threads.
class CholeskyAnalysis {
 public:
  CholeskyAnalysis();
  ~CholeskyAnalysis();
  CholeskyAnalysis(const CholeskyAnalysis&) = delete;
  CholeskyAnalysis& operator=(const CholeskyAnalysis&) = delete;

  // The numeric factorization of A (analysed again when its pattern differs from the last
  // one). Returns null and says why in *error when A is not positive definite (or CHOLMOD
  // fails otherwise). The factor owns its memory and may be handed to another thread.
  std::unique_ptr<CholeskyFactor> factor(const CsrMatrix& A, std::string* error);

 private:
  struct State;
  std::unique_ptr<State> state_;
};

class CholeskyFactor {
 public:
  ~CholeskyFactor();
  CholeskyFactor(const CholeskyFactor&) = delete;
  CholeskyFactor& operator=(const CholeskyFactor&) = delete;

  int size() const;
  // x = A^-1 b (x and b of size(); may be the same array). One thread at a time.
  void solve(const double* b, double* x);

 private:
  friend class CholeskyAnalysis;
  CholeskyFactor();
  struct State;
  std::unique_ptr<State> state_;
};

// Keeps OpenMP regions (CHOLMOD's, of a fixed four threads in Debian's build) to one thread,
// process-wide: the cores are the ranks' and the factorization threads', and four threads
// per factorization on a 2-core machine fight over them.
void limit_openmp_to_one_thread();

}  // namespace hs
