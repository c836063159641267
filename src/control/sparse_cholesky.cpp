#include "control/sparse_cholesky.hpp"

#include <cholmod.h>
#include <dlfcn.h>

#include <cstring>
#include <stdexcept>

namespace hs {
namespace {

void start(cholmod_common& c) {
  cholmod_start(&c);
  c.print = 0;  // a matrix that is not positive definite is reported by the caller
  c.error_handler = nullptr;
  c.supernodal = CHOLMOD_SUPERNODAL;
  // AMD alone: the nested dissections cost more to analyse and gave slower factorizations
  // of the finger's tangent (docs/control.md).
  c.nmethods = 1;
  c.method[0].ordering = CHOLMOD_AMD;
}

// A non-owning CHOLMOD view of the CSR arrays: the rows of A are the columns of A^T = A, so
// stype = 1 (the upper triangle of the column view) reads each row's entries up to the
// diagonal.
cholmod_sparse view(const CsrMatrix& A) {
  cholmod_sparse s{};
  s.nrow = s.ncol = A.n;
  s.nzmax = A.column.size();
  s.p = const_cast<int*>(A.row_start.data());
  s.i = const_cast<int*>(A.column.data());
  s.x = const_cast<double*>(A.value.data());
  s.stype = 1;
  s.itype = CHOLMOD_INT;
  s.xtype = CHOLMOD_REAL;
  s.dtype = CHOLMOD_DOUBLE;
  s.sorted = 1;
  s.packed = 1;
  return s;
}

}  // namespace

struct CholeskyAnalysis::State {
  cholmod_common common;
  cholmod_factor* symbolic = nullptr;
  std::vector<int> row_start, column;  // the pattern analysed
};

struct CholeskyFactor::State {
  cholmod_common common;
  cholmod_factor* L = nullptr;
  cholmod_dense* b = nullptr;
  cholmod_dense *x = nullptr, *y = nullptr, *e = nullptr;  // cholmod_solve2's workspaces
};

CholeskyAnalysis::CholeskyAnalysis() : state_(std::make_unique<State>()) { start(state_->common); }

CholeskyAnalysis::~CholeskyAnalysis() {
  cholmod_free_factor(&state_->symbolic, &state_->common);
  cholmod_finish(&state_->common);
}

std::unique_ptr<CholeskyFactor> CholeskyAnalysis::factor(const CsrMatrix& A, std::string* error) {
  cholmod_sparse a = view(A);
  State& s = *state_;
  if (!s.symbolic || s.row_start != A.row_start || s.column != A.column) {
    cholmod_free_factor(&s.symbolic, &s.common);
    s.symbolic = cholmod_analyze(&a, &s.common);
    if (!s.symbolic) {
      if (error)
        *error = "CHOLMOD: the analysis failed (status " + std::to_string(s.common.status) + ")";
      return nullptr;
    }
    s.row_start = A.row_start;
    s.column = A.column;
  }
  std::unique_ptr<CholeskyFactor> f(new CholeskyFactor());
  cholmod_common& c = f->state_->common;
  f->state_->L = cholmod_copy_factor(s.symbolic, &c);
  if (f->state_->L) cholmod_factorize(&a, f->state_->L, &c);
  if (!f->state_->L || c.status != CHOLMOD_OK || f->state_->L->minor < f->state_->L->n) {
    if (error) {
      if (c.status == CHOLMOD_NOT_POSDEF || (f->state_->L && f->state_->L->minor < f->state_->L->n))
        *error = "not positive definite (CHOLMOD stopped at column " +
                 std::to_string(f->state_->L ? f->state_->L->minor : 0) + " of " +
                 std::to_string(A.n) + ")";
      else
        *error = "CHOLMOD failed (status " + std::to_string(c.status) + ")";
    }
    return nullptr;
  }
  f->state_->b = cholmod_zeros(A.n, 1, CHOLMOD_REAL, &c);
  return f;
}

CholeskyFactor::CholeskyFactor() : state_(std::make_unique<State>()) { start(state_->common); }

CholeskyFactor::~CholeskyFactor() {
  State& s = *state_;
  for (cholmod_dense** d : {&s.b, &s.x, &s.y, &s.e}) cholmod_free_dense(d, &s.common);
  cholmod_free_factor(&s.L, &s.common);
  cholmod_finish(&s.common);
}

int CholeskyFactor::size() const { return static_cast<int>(state_->L->n); }

void CholeskyFactor::solve(const double* b, double* x) {
  State& s = *state_;
  const size_t n = s.L->n;
  std::memcpy(s.b->x, b, n * sizeof(double));
  if (!cholmod_solve2(CHOLMOD_A, s.L, s.b, nullptr, &s.x, nullptr, &s.y, &s.e, &s.common))
    throw std::runtime_error("CHOLMOD: a solve failed");
  std::memcpy(x, s.x->x, n * sizeof(double));
}

void limit_openmp_to_one_thread() {
  // Looked up rather than linked: CHOLMOD brings the OpenMP runtime, the project does not
  // use it otherwise. max-active-levels 0 makes every parallel region run on one thread.
  using SetLevels = void (*)(int);
  if (auto set = reinterpret_cast<SetLevels>(dlsym(RTLD_DEFAULT, "omp_set_max_active_levels")))
    set(0);
}

}  // namespace hs
