#include "solvers/multi_solve.hpp"

#include <cstring>

#include "solvers/mixed_factor.hpp"
#include "solvers/petsc_check.hpp"
#include "solvers/petsc_handle.hpp"
#include "solvers/solver_options.hpp"

namespace hs {

bool solve_columns(KSP ksp, const std::vector<Vec>& b, const std::vector<Vec>& x, int* iterations) {
  if (b.empty()) return true;
  const OptionsScope scope(reinterpret_cast<PetscObject>(ksp));  // its factor's, its levels'
  KSPType type;
  HS_PETSC(KSPGetType(ksp, &type));
  PC pc;
  HS_PETSC(KSPGetPC(ksp, &pc));
  PetscBool factored = PETSC_FALSE;
  HS_PETSC(PetscObjectTypeCompareAny(reinterpret_cast<PetscObject>(pc), &factored, PCLU, PCCHOLESKY,
                                     ""));
  PetscBool mixed = PETSC_FALSE;  // solvers/mixed_factor.hpp: PCMatApply solves them at once
  HS_PETSC(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), kMixedFactorType, &mixed));
  Mat F = nullptr;
  PetscBool together = PETSC_FALSE;
  if (b.size() > 1 && (factored || mixed) && std::strcmp(type, KSPPREONLY) == 0) {
    HS_PETSC(KSPSetUp(ksp));
    if (mixed) {
      together = PETSC_TRUE;
    } else {
      HS_PETSC(PCFactorGetMatrix(pc, &F));
      HS_PETSC(MatHasOperation(F, MATOP_MAT_SOLVE, &together));
    }
  }
  if (!together) {
    bool ok = true;
    for (size_t j = 0; j < b.size(); ++j) {
      HS_PETSC(KSPSolve(ksp, b[j], x[j]));
      KSPConvergedReason reason;
      HS_PETSC(KSPGetConvergedReason(ksp, &reason));
      PetscInt its = 0;
      HS_PETSC(KSPGetIterationNumber(ksp, &its));
      if (iterations) *iterations += static_cast<int>(its);
      ok &= reason >= 0;
    }
    return ok;
  }
  PCFailedReason failed;
  HS_PETSC(PCGetFailedReasonRank(pc, &failed));
  int local_failed = failed != PC_NOERROR, any_failed = 0;
  MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(ksp));
  MPI_Allreduce(&local_failed, &any_failed, 1, MPI_INT, MPI_MAX, comm);
  if (any_failed) return false;
  PetscInt n_local = 0, n = 0;
  HS_PETSC(VecGetLocalSize(b[0], &n_local));
  HS_PETSC(VecGetSize(b[0], &n));
  const PetscInt k = static_cast<PetscInt>(b.size());
  MatHandle B, X;
  HS_PETSC(MatCreateDense(comm, n_local, PETSC_DECIDE, n, k, nullptr, B.out()));
  HS_PETSC(MatCreateDense(comm, n_local, PETSC_DECIDE, n, k, nullptr, X.out()));
  for (PetscInt j = 0; j < k; ++j) {
    Vec column;
    HS_PETSC(MatDenseGetColumnVecWrite(B, j, &column));
    HS_PETSC(VecCopy(b[j], column));
    HS_PETSC(MatDenseRestoreColumnVecWrite(B, j, &column));
  }
  if (mixed)
    HS_PETSC(PCMatApply(pc, B, X));
  else
    HS_PETSC(MatMatSolve(F, B, X));
  for (PetscInt j = 0; j < k; ++j) {
    Vec column;
    HS_PETSC(MatDenseGetColumnVecRead(X, j, &column));
    HS_PETSC(VecCopy(column, x[j]));
    HS_PETSC(MatDenseRestoreColumnVecRead(X, j, &column));
  }
  return true;
}

}  // namespace hs
