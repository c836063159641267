#include "solvers/mixed_factor.hpp"

// A preconditioner type of its own needs PETSc's private PC structure (its operations and
// data); PETSc's own types are written against it.
#include <petsc/private/pcimpl.h>

#include <cstring>

namespace hs {
namespace {

struct MixedFactor {
  KSP solve = nullptr;                    // preonly + MUMPS on the mixed system
  Vec b = nullptr, x = nullptr;           // the mixed system's right-hand side and solution
  PetscInt negative_pressure_pivots = 0;  // negative entries of -D^-1, all ranks
  char factor[16] = "cholesky";
};

PetscErrorCode destroy(PC pc) {
  auto* m = static_cast<MixedFactor*>(pc->data);
  PetscCall(KSPDestroy(&m->solve));
  PetscCall(VecDestroy(&m->b));
  PetscCall(VecDestroy(&m->x));
  delete m;
  pc->data = nullptr;
  return 0;
}

PetscErrorCode set_from_options(PC pc, PetscOptionItems* PetscOptionsObject) {
  auto* m = static_cast<MixedFactor*>(pc->data);
  const char* kinds[] = {"cholesky", "lu"};
  PetscInt kind = std::strcmp(m->factor, "lu") == 0;
  PetscOptionsHeadBegin(PetscOptionsObject, "hs_mixed: the nodal-pressure tangent's mixed system");
  PetscCall(PetscOptionsEList("-pc_mixed_factor_type",
                              "L D L^T of the symmetric system or LU of a non-symmetric one",
                              "hs_mixed", kinds, 2, kinds[kind], &kind, nullptr));
  PetscOptionsHeadEnd();
  std::strcpy(m->factor, kinds[kind]);
  return 0;
}

// The pressure rows of each rank follow its displacement rows: those past J's local rows.
PetscErrorCode count_negative_pressure_pivots(Mat A, PetscInt displacement_rows, PetscInt* count) {
  Vec diagonal;
  PetscCall(MatCreateVecs(A, nullptr, &diagonal));
  PetscCall(MatGetDiagonal(A, diagonal));
  PetscInt n;
  const PetscScalar* d;
  PetscCall(VecGetLocalSize(diagonal, &n));
  PetscCall(VecGetArrayRead(diagonal, &d));
  PetscInt local = 0;
  for (PetscInt i = displacement_rows; i < n; ++i) local += d[i] < 0;
  PetscCall(VecRestoreArrayRead(diagonal, &d));
  PetscCall(VecDestroy(&diagonal));
  PetscCallMPI(MPI_Allreduce(&local, count, 1, MPIU_INT, MPI_SUM, PetscObjectComm((PetscObject)A)));
  return 0;
}

PetscErrorCode set_up(PC pc) {
  auto* m = static_cast<MixedFactor*>(pc->data);
  PetscObject composed = nullptr;
  PetscCall(PetscObjectQuery((PetscObject)pc->pmat, kMixedTangentKey, &composed));
  if (!composed)
    SETERRQ(PetscObjectComm((PetscObject)pc), PETSC_ERR_ARG_WRONG,
            "pc_type hs_mixed needs the tangent of a body with nodal pressures (formulation "
            "nodal_pressure); use pc_type cholesky or lu");
  Mat A = (Mat)composed;
  if (!m->solve) {
    PetscCall(KSPCreate(PetscObjectComm((PetscObject)pc), &m->solve));
    PetscOptions options;
    PetscCall(PetscObjectGetOptions((PetscObject)pc, &options));
    PetscCall(PetscObjectSetOptions((PetscObject)m->solve, options));
    const char* prefix = nullptr;  // MUMPS's options (-mat_mumps_icntl_14, ...) are the PC's
    PetscCall(PCGetOptionsPrefix(pc, &prefix));
    PetscCall(KSPSetOptionsPrefix(m->solve, prefix));
    PetscCall(KSPSetType(m->solve, KSPPREONLY));
    PC factor;
    PetscCall(KSPGetPC(m->solve, &factor));
    PetscCall(PCSetType(factor, std::strcmp(m->factor, "lu") == 0 ? PCLU : PCCHOLESKY));
    PetscCall(PCFactorSetMatSolverType(factor, MATSOLVERMUMPS));
    PetscCall(KSPSetErrorIfNotConverged(m->solve, PETSC_FALSE));
    PetscCall(MatCreateVecs(A, &m->x, &m->b));
  }
  PetscCall(KSPSetOperators(m->solve, A, A));
  PetscCall(KSPSetUp(m->solve));
  PC factor;
  PetscCall(KSPGetPC(m->solve, &factor));
  PCFailedReason failed;
  PetscCall(PCGetFailedReasonRank(factor, &failed));
  pc->failedreason = pc->failedreasonrank = failed;
  PetscInt rows;
  PetscCall(MatGetLocalSize(pc->pmat, &rows, nullptr));
  PetscCall(count_negative_pressure_pivots(A, rows, &m->negative_pressure_pivots));
  return 0;
}

// x = J^-1 b: b padded with zeros in the pressure rows, the displacement rows of the solution.
PetscErrorCode apply(PC pc, Vec b, Vec x) {
  auto* m = static_cast<MixedFactor*>(pc->data);
  PetscInt n;
  PetscCall(VecGetLocalSize(b, &n));
  const PetscScalar* from;
  PetscScalar* to;
  PetscCall(VecSet(m->b, 0.0));
  PetscCall(VecGetArrayRead(b, &from));
  PetscCall(VecGetArray(m->b, &to));
  std::memcpy(to, from, sizeof(PetscScalar) * n);
  PetscCall(VecRestoreArray(m->b, &to));
  PetscCall(VecRestoreArrayRead(b, &from));
  PetscCall(KSPSolve(m->solve, m->b, m->x));
  KSPConvergedReason reason;
  PetscCall(KSPGetConvergedReason(m->solve, &reason));
  if (reason < 0) pc->failedreason = pc->failedreasonrank = PC_SUBPC_ERROR;
  PetscCall(VecGetArrayRead(m->x, &from));
  PetscCall(VecGetArray(x, &to));
  std::memcpy(to, from, sizeof(PetscScalar) * n);
  PetscCall(VecRestoreArray(x, &to));
  PetscCall(VecRestoreArrayRead(m->x, &from));
  return 0;
}

// X = J^-1 B, column by column at once (the controller's compliance): B padded as in apply.
PetscErrorCode mat_apply(PC pc, Mat B, Mat X) {
  auto* m = static_cast<MixedFactor*>(pc->data);
  PetscInt n, k, n_mixed;
  PetscCall(MatGetLocalSize(B, &n, nullptr));
  PetscCall(MatGetSize(B, nullptr, &k));
  PetscCall(VecGetLocalSize(m->b, &n_mixed));
  Mat Bm, Xm;
  PetscCall(MatCreateDense(PetscObjectComm((PetscObject)pc), n_mixed, PETSC_DECIDE, PETSC_DETERMINE,
                           k, nullptr, &Bm));
  PetscCall(MatDuplicate(Bm, MAT_DO_NOT_COPY_VALUES, &Xm));
  auto copy_rows = [&](Mat from, Mat to) -> PetscErrorCode {  // the first n rows of each column
    const PetscScalar* a;
    PetscScalar* b;
    PetscInt lda_from, lda_to;
    PetscCall(MatDenseGetLDA(from, &lda_from));
    PetscCall(MatDenseGetLDA(to, &lda_to));
    PetscCall(MatDenseGetArrayRead(from, &a));
    PetscCall(MatDenseGetArray(to, &b));
    for (PetscInt j = 0; j < k; ++j)
      std::memcpy(b + j * lda_to, a + j * lda_from, sizeof(PetscScalar) * n);
    PetscCall(MatDenseRestoreArray(to, &b));
    PetscCall(MatDenseRestoreArrayRead(from, &a));
    return 0;
  };
  PetscCall(MatZeroEntries(Bm));
  PetscCall(copy_rows(B, Bm));
  PC factor;
  Mat F;
  PetscCall(KSPGetPC(m->solve, &factor));
  PetscCall(PCFactorGetMatrix(factor, &F));
  PetscCall(MatMatSolve(F, Bm, Xm));
  PetscCall(copy_rows(Xm, X));
  PetscCall(MatDestroy(&Bm));
  PetscCall(MatDestroy(&Xm));
  return 0;
}

PetscErrorCode view(PC pc, PetscViewer viewer) {
  auto* m = static_cast<MixedFactor*>(pc->data);
  PetscBool ascii;
  PetscCall(PetscObjectTypeCompare((PetscObject)viewer, PETSCVIEWERASCII, &ascii));
  if (!ascii) return 0;
  PetscCall(PetscViewerASCIIPrintf(
      viewer, "  the tangent solved through its mixed system (displacements, nodal pressures)\n"));
  if (!m->solve) return 0;
  PetscCall(PetscViewerASCIIPushTab(viewer));
  PetscCall(KSPView(m->solve, viewer));
  PetscCall(PetscViewerASCIIPopTab(viewer));
  return 0;
}

PetscErrorCode create(PC pc) {
  pc->data = new MixedFactor;
  pc->ops->setup = set_up;
  pc->ops->apply = apply;
  pc->ops->matapply = mat_apply;
  pc->ops->applytranspose = nullptr;
  pc->ops->setfromoptions = set_from_options;
  pc->ops->destroy = destroy;
  pc->ops->view = view;
  return 0;
}

}  // namespace

void register_mixed_factor() {
  static const PetscErrorCode registered = PCRegister(kMixedFactorType, create);
  (void)registered;
}

int mixed_factor_negative_pivots(PC pc) {
  PetscBool mixed = PETSC_FALSE;
  PetscObjectTypeCompare((PetscObject)pc, kMixedFactorType, &mixed);
  if (!mixed) return -1;
  auto* m = static_cast<MixedFactor*>(pc->data);
  if (!m->solve) return -1;
  PC factor;
  Mat F;
  KSPGetPC(m->solve, &factor);
  if (PCFactorGetMatrix(factor, &F)) return -1;
  PetscInt negative = 0;
  if (MatMumpsGetInfog(F, 12, &negative)) return -1;
  return static_cast<int>(negative - m->negative_pressure_pivots);
}

}  // namespace hs
