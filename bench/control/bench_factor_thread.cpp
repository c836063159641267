// The background factorization's candidate against MUMPS (bench_factor.cpp) on a tangent
// written by a run (-ksp_view_mat binary:K.bin, see bench_factor.cpp):
//
//   build/bin/bench_factor_thread /tmp/K.bin [-repeats 9]
//
// Prints medians over -repeats of: CHOLMOD's numeric factorization (supernodal L L^T, AMD)
// in the calling thread, with CHOLMOD's OpenMP regions as Debian builds them and then kept to
// one thread; its solve; the copy of the tangent out of PETSc (CSR); and the factorization
// made by a FactorPool thread while the calling thread solves with the previous factor
// without pause, as the control loop would (the solves' median there shows what the two
// cores cost each other).
#include <petscmat.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "control/factor_pool.hpp"

namespace {

#define CHECK(call)                                             \
  do {                                                          \
    if ((call) != 0) throw std::runtime_error("PETSc: " #call); \
  } while (0)

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

hs::CsrMatrix csr_of(Mat A) {
  PetscInt n;
  const PetscInt *ia, *ja;
  PetscBool done;
  const PetscScalar* a;
  CHECK(MatGetRowIJ(A, 0, PETSC_FALSE, PETSC_FALSE, &n, &ia, &ja, &done));
  CHECK(MatSeqAIJGetArrayRead(A, &a));
  hs::CsrMatrix m;
  m.n = n;
  m.row_start.assign(ia, ia + n + 1);
  m.column.assign(ja, ja + ia[n]);
  m.value.assign(a, a + ia[n]);
  CHECK(MatSeqAIJRestoreArrayRead(A, &a));
  CHECK(MatRestoreRowIJ(A, 0, PETSC_FALSE, PETSC_FALSE, &n, &ia, &ja, &done));
  return m;
}

void run(const char* path) {
  PetscViewer viewer;
  Mat A;
  CHECK(PetscViewerBinaryOpen(PETSC_COMM_SELF, path, FILE_MODE_READ, &viewer));
  CHECK(MatCreate(PETSC_COMM_SELF, &A));
  CHECK(MatSetType(A, MATSEQAIJ));
  CHECK(MatLoad(A, viewer));
  CHECK(PetscViewerDestroy(&viewer));
  PetscInt repeats = 9;
  CHECK(PetscOptionsGetInt(nullptr, nullptr, "-repeats", &repeats, nullptr));
  std::vector<double> copy_s;
  hs::CsrMatrix K;
  for (int r = 0; r < repeats; ++r) {
    const double t = now();
    K = csr_of(A);
    copy_s.push_back(now() - t);
  }
  std::vector<double> b(K.n, 1.0), x(K.n);
  auto time_factor = [&](const char* what) {
    hs::CholeskyAnalysis analysis;
    std::string error;
    std::vector<double> factor_s, solve_s;
    std::unique_ptr<hs::CholeskyFactor> f;
    for (int r = 0; r < repeats; ++r) {
      const double t = now();
      f = analysis.factor(K, &error);
      factor_s.push_back(now() - t);
      if (!f) throw std::runtime_error("CHOLMOD: " + error);
      const double t1 = now();
      f->solve(b.data(), x.data());
      solve_s.push_back(now() - t1);
    }
    std::printf("cholmod %-28s factor %7.2f ms  solve %5.2f ms\n", what, 1e3 * median(factor_s),
                1e3 * median(solve_s));
    return f;
  };
  time_factor("(OpenMP as built)");
  hs::limit_openmp_to_one_thread();
  std::unique_ptr<hs::CholeskyFactor> previous = time_factor("(OpenMP one thread)");
  std::printf("copy of the tangent (CSR)            %7.2f ms\n", 1e3 * median(copy_s));

  hs::FactorPool pool(1);
  std::vector<double> latency, busy_solve;
  for (int r = 0; r < repeats; ++r) {
    hs::CsrMatrix copy = K;
    const double t = now();
    pool.submit(copy, r);
    std::vector<hs::FactorResult> done;
    while (done.empty()) {
      const double t1 = now();
      previous->solve(b.data(), x.data());
      busy_solve.push_back(now() - t1);
      done = pool.take_finished();
    }
    latency.push_back(now() - t);
    if (!done[0].factor) throw std::runtime_error("CHOLMOD: " + done[0].error);
    previous = std::move(done[0].factor);
  }
  std::printf("in a thread, while solving: latency  %7.2f ms  solves meanwhile %5.2f ms\n",
              1e3 * median(latency), 1e3 * median(busy_solve));
  CHECK(MatDestroy(&A));
}

}  // namespace

int main(int argc, char** argv) {
  if (PetscInitialize(&argc, &argv, nullptr, nullptr)) return 1;
  int status = 0;
  try {
    if (argc < 2) throw std::runtime_error("usage: bench_factor_thread K.bin [-repeats N]");
    run(argv[1]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_factor_thread: %s\n", e.what());
    status = 1;
  }
  PetscFinalize();
  return status;
}
