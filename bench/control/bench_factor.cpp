// Factorization and solve times of one tangent, for choosing a direct solver for the control
// step (docs/control.md, "Time per control step"). The tangent comes from a run:
//
//   build/bin/hydrosoft input/finger_hydraulic.yaml --set control.steps_per_target=3
//       --set control.free_solve=one_step --set control.refactor_every=4
//       --set "control.targets=[{tip: [0.09, 0, -0.012]}]" --set output.folder=/tmp/k
//       -ksp_view_mat binary:/tmp/K.bin::append
//
// (A kept factorization's step is the only KSPSolve of such a run: the cavities' bordered
// Newton and a refactoring step solve through MatMatSolve, solvers/multi_solve.cpp, so with
// refactor_every=1 the file stays empty. Readers take the first matrix of the file.)
//
//   build/bin/bench_factor /tmp/K.bin -pc_factor_mat_solver_type mumps [-mat_mumps_icntl_7 5]
//
// Every PETSc option applies (the KSP is preonly + Cholesky unless told otherwise; -spd
// declares the matrix SPD). Prints the median over -repeats (default 9) of a numeric
// refactorization (values changed, pattern kept, as in a control step), of the first solve
// after it and of a later one, and the relative residual of the last solve.
#include <petscksp.h>

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#define CHECK(call)                                             \
  do {                                                          \
    if ((call) != 0) throw std::runtime_error("PETSc: " #call); \
  } while (0)

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

void run(const char* path) {
  PetscViewer viewer;
  Mat A;
  CHECK(PetscViewerBinaryOpen(PETSC_COMM_WORLD, path, FILE_MODE_READ, &viewer));
  CHECK(MatCreate(PETSC_COMM_WORLD, &A));
  CHECK(MatSetType(A, MATAIJ));
  CHECK(MatLoad(A, viewer));
  CHECK(PetscViewerDestroy(&viewer));
  PetscBool spd = PETSC_FALSE;
  PetscInt repeats = 9;
  CHECK(PetscOptionsGetBool(nullptr, nullptr, "-spd", &spd, nullptr));
  CHECK(PetscOptionsGetInt(nullptr, nullptr, "-repeats", &repeats, nullptr));
  if (spd) CHECK(MatSetOption(A, MAT_SPD, PETSC_TRUE));
  Vec x, b, r;
  CHECK(MatCreateVecs(A, &x, &b));
  CHECK(VecDuplicate(b, &r));
  CHECK(VecSetRandom(b, nullptr));
  KSP ksp;
  PC pc;
  CHECK(KSPCreate(PETSC_COMM_WORLD, &ksp));
  CHECK(KSPSetType(ksp, KSPPREONLY));
  CHECK(KSPGetPC(ksp, &pc));
  CHECK(PCSetType(pc, PCCHOLESKY));
  CHECK(KSPSetOperators(ksp, A, A));
  CHECK(KSPSetFromOptions(ksp));
  double t = MPI_Wtime();
  CHECK(KSPSetUp(ksp));
  const double first = MPI_Wtime() - t;
  std::vector<double> factor, solve_first, solve_later;
  for (PetscInt k = 0; k < repeats; ++k) {
    CHECK(MatScale(A, k % 2 ? 1.0 / 1.0000001 : 1.0000001));  // new values, same pattern
    t = MPI_Wtime();
    CHECK(KSPSetOperators(ksp, A, A));
    CHECK(KSPSetUp(ksp));
    factor.push_back(MPI_Wtime() - t);
    t = MPI_Wtime();
    CHECK(KSPSolve(ksp, b, x));
    solve_first.push_back(MPI_Wtime() - t);
    t = MPI_Wtime();
    CHECK(KSPSolve(ksp, b, x));
    solve_later.push_back(MPI_Wtime() - t);
  }
  CHECK(MatMult(A, x, r));
  CHECK(VecAXPY(r, -1.0, b));
  PetscReal nr = 0, nb = 0;
  CHECK(VecNorm(r, NORM_2, &nr));
  CHECK(VecNorm(b, NORM_2, &nb));
  PetscInt n = 0;
  CHECK(MatGetSize(A, &n, nullptr));
  CHECK(PetscPrintf(PETSC_COMM_WORLD,
                    "{\"n\": %d, \"first_setup_ms\": %.3f, \"refactor_ms\": %.3f, "
                    "\"solve_first_ms\": %.3f, \"solve_later_ms\": %.3f, \"relres\": %.2e}\n",
                    static_cast<int>(n), 1e3 * first, 1e3 * median(factor),
                    1e3 * median(solve_first), 1e3 * median(solve_later),
                    static_cast<double>(nr / nb)));
  KSPDestroy(&ksp);
  VecDestroy(&x);
  VecDestroy(&b);
  VecDestroy(&r);
  MatDestroy(&A);
}

}  // namespace

int main(int argc, char** argv) {
  if (PetscInitialize(&argc, &argv, nullptr, nullptr) != 0) return 1;
  int rc = 0;
  if (argc < 2 || argv[1][0] == '-') {
    std::fprintf(stderr, "usage: bench_factor MATRIX.bin [PETSc options]\n");
    rc = 2;
  } else {
    try {
      run(argv[1]);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "bench_factor: %s: %s\n", argv[1], e.what());
      rc = 1;
    }
  }
  PetscFinalize();
  return rc;
}
