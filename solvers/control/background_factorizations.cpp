#include "solvers/control/background_factorizations.hpp"

#include <stdexcept>

#include "common/exchange.hpp"
#include "solvers/petsc_check.hpp"
#include "solvers/petsc_handle.hpp"

namespace hs {
namespace {

// The rows of a sequential AIJ matrix, copied.
CsrMatrix csr_of(Mat A) {
  PetscInt n;
  const PetscInt *ia, *ja;
  PetscBool done;
  const PetscScalar* a;
  HS_PETSC(MatGetRowIJ(A, 0, PETSC_FALSE, PETSC_FALSE, &n, &ia, &ja, &done));
  if (!done) throw std::runtime_error("background factorization: no rows of the tangent");
  HS_PETSC(MatSeqAIJGetArrayRead(A, &a));
  CsrMatrix m;
  m.n = static_cast<int>(n);
  m.row_start.assign(ia, ia + n + 1);
  m.column.assign(ja, ja + ia[n]);
  m.value.assign(a, a + ia[n]);
  HS_PETSC(MatSeqAIJRestoreArrayRead(A, &a));
  HS_PETSC(MatRestoreRowIJ(A, 0, PETSC_FALSE, PETSC_FALSE, &n, &ia, &ja, &done));
  return m;
}

// MatCreateSubMatrices' array (of one matrix here), released as the handles release theirs.
PetscErrorCode destroy_submatrix(Mat** whole) { return MatDestroySubMatrices(1, whole); }
using SubMatrixHandle = PetscHandle<Mat*, destroy_submatrix>;

}  // namespace

BackgroundFactorizations::BackgroundFactorizations(MPI_Comm comm, int threads, KSP inline_ksp,
                                                   double rtol, const SolverConfig& solver)
    : comm_(comm),
      threads_(threads),
      inline_ksp_(inline_ksp),
      // Its solver is set here (GMRES on the kept factorization): no preset, and only the
      // options with its prefix, as before each object had its own.
      options_(kCorrectionPrefix, solver, {}, SolverOptions::Reach::own_prefix_only) {
  MPI_Comm_rank(comm, &rank_);
  if (rank_ == 0) {
    limit_openmp_to_one_thread();
    pool_ = std::make_unique<FactorPool>(threads);
  }
  HS_PETSC(KSPCreate(comm, correction_.out()));
  options_.attach(reinterpret_cast<PetscObject>(correction_.get()));
  HS_PETSC(KSPSetType(correction_, KSPGMRES));
  HS_PETSC(KSPSetPCSide(correction_, PC_RIGHT));  // its residual is the true residual
  HS_PETSC(KSPSetTolerances(correction_, rtol, 0.0, PETSC_DEFAULT, 50));
  PC pc;
  HS_PETSC(KSPGetPC(correction_, &pc));
  HS_PETSC(PCSetType(pc, PCSHELL));
  HS_PETSC(PCShellSetContext(pc, this));
  HS_PETSC(PCShellSetApply(pc, &BackgroundFactorizations::apply));
  HS_PETSC(KSPSetOptionsPrefix(correction_, kCorrectionPrefix));
  HS_PETSC(KSPSetFromOptions(correction_));
}

BackgroundFactorizations::~BackgroundFactorizations() {
  pool_.reset();  // joins the threads first; the PETSc objects go after
}

BackgroundFactorizations::Poll BackgroundFactorizations::poll() {
  Poll p;
  int adopted_state = -1;
  if (rank_ == 0) {
    for (FactorResult& r : pool_->take_finished()) {
      if (!r.factor) {
        p.failed = true;
        p.error = "the background factorization of step " + std::to_string(r.state) +
                  "'s tangent failed: " + r.error;
      } else if (r.state > state_ && r.state > adopted_state) {
        factor_ = std::move(r.factor);
        adopted_state = r.state;
        p.factor_ms = 1e3 * r.seconds;
      }
    }
  }
  int flags[2] = {p.failed, adopted_state};
  MPI_Bcast(flags, 2, MPI_INT, 0, comm_);
  p.failed = flags[0];
  adopted_state = flags[1];
  MPI_Bcast(&p.factor_ms, 1, MPI_DOUBLE, 0, comm_);
  broadcast_string(p.error, 0, comm_);
  if (adopted_state >= 0) {
    p.adopted = true;
    source_ = Source::background;
    state_ = adopted_state;
  }
  return p;
}

void BackgroundFactorizations::use_inline(int state) {
  // The in-line KSP keeps this factorization while its matrix is assembled again for the
  // steps after (their tangents are the correction's operator, not its preconditioner).
  HS_PETSC(KSPSetReusePreconditioner(inline_ksp_, PETSC_TRUE));
  source_ = Source::inline_ksp;
  state_ = state;
}

bool BackgroundFactorizations::submit_if_idle(Mat J, int state) {
  int idle = rank_ == 0 && pool_->idle();
  MPI_Bcast(&idle, 1, MPI_INT, 0, comm_);
  if (!idle) return false;
  PetscInt n = 0;
  HS_PETSC(MatGetSize(J, &n, nullptr));
  IsHandle rows;
  HS_PETSC(ISCreateStride(comm_, rank_ == 0 ? n : 0, 0, 1, rows.out()));
  SubMatrixHandle whole;
  const IS row_list[1] = {rows};
  HS_PETSC(MatCreateSubMatrices(J, 1, row_list, row_list, MAT_INITIAL_MATRIX, whole.out()));
  if (rank_ == 0) {
    CsrMatrix A = csr_of(whole.get()[0]);
    if (filter_) filter_(A);
    pool_->submit(A, state);
  }
  return true;
}

KSP BackgroundFactorizations::correction(Mat J) {
  HS_PETSC(KSPSetOperators(correction_, J, J));
  return correction_;
}

void BackgroundFactorizations::wait_idle() {
  if (rank_ == 0) pool_->wait_idle();
  MPI_Barrier(comm_);
}

PetscErrorCode BackgroundFactorizations::apply(PC pc, Vec x, Vec y) {
  PetscFunctionBeginUser;
  BackgroundFactorizations* self = nullptr;
  PetscCall(PCShellGetContext(pc, &self));
  if (self->source_ == Source::inline_ksp) {
    PetscCall(KSPSolve(self->inline_ksp_, x, y));
    PetscFunctionReturn(0);
  }
  if (!self->to_zero_) PetscCall(VecScatterCreateToZero(x, self->to_zero_.out(), self->x0_.out()));
  if (!self->y0_) PetscCall(VecDuplicate(self->x0_, self->y0_.out()));
  PetscCall(VecScatterBegin(self->to_zero_, x, self->x0_, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(self->to_zero_, x, self->x0_, INSERT_VALUES, SCATTER_FORWARD));
  if (self->rank_ == 0) {
    const PetscScalar* in;
    PetscScalar* out;
    PetscCall(VecGetArrayRead(self->x0_, &in));
    PetscCall(VecGetArray(self->y0_, &out));
    try {
      self->factor_->solve(in, out);
    } catch (const std::exception&) {
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_LIB, "CHOLMOD: a solve with the factorization failed");
    }
    PetscCall(VecRestoreArray(self->y0_, &out));
    PetscCall(VecRestoreArrayRead(self->x0_, &in));
  }
  PetscCall(VecScatterBegin(self->to_zero_, self->y0_, y, INSERT_VALUES, SCATTER_REVERSE));
  PetscCall(VecScatterEnd(self->to_zero_, self->y0_, y, INSERT_VALUES, SCATTER_REVERSE));
  PetscFunctionReturn(0);
}

}  // namespace hs
