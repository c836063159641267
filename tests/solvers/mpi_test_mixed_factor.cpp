// The nodal-pressure tangent solved through its mixed system (solvers/mixed_factor.hpp), on 1
// and 2 ranks: the same solutions as MUMPS on the assembled tangent, one right-hand side or
// several at once, with the inertia of a time step, and its count of negative eigenvalues
// against a matrix whose inertia is known by hand; and the one BLAS thread a rank its dense
// fronts run on unless the user chose otherwise.
#include <dlfcn.h>
#include <gtest/gtest.h>
#include <petscksp.h>

#include <random>
#include <string>
#include <vector>

#include "deck/deck.hpp"
#include "materials/registry.hpp"
#include "solvers/blas_threads.hpp"
#include "solvers/distributed_mesh.hpp"
#include "solvers/mixed_factor.hpp"
#include "solvers/multi_solve.hpp"
#include "solvers/problem.hpp"

namespace {
namespace mpi_test_mixed_factor {

const std::string kSource = HYDROSOFT_SOURCE_DIR;

void fill_random(Vec v, double scale, unsigned seed) {
  PetscInt lo, hi;
  VecGetOwnershipRange(v, &lo, &hi);
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> d(-scale, scale);
  for (PetscInt i = 0; i < hi; ++i) {  // the same values on any number of ranks
    const double x = d(gen);
    if (i >= lo) VecSetValue(v, i, x, INSERT_VALUES);
  }
  VecAssemblyBegin(v);
  VecAssemblyEnd(v);
}

// A direct solver on J: MUMPS on the assembled tangent, or the mixed system's.
hs::KspHandle direct_solver(Mat J, const char* pc_type) {
  hs::register_mixed_factor();
  hs::KspHandle ksp;
  KSPCreate(PetscObjectComm(reinterpret_cast<PetscObject>(J)), ksp.out());
  KSPSetOperators(ksp, J, J);
  KSPSetType(ksp, KSPPREONLY);
  PC pc;
  KSPGetPC(ksp, &pc);
  PCSetType(pc, pc_type);
  if (std::string(pc_type) == PCCHOLESKY) PCFactorSetMatSolverType(pc, MATSOLVERMUMPS);
  KSPSetUp(ksp);
  return ksp;
}

double relative_difference(Vec a, Vec b) {
  hs::VecHandle d;
  VecDuplicate(a, d.out());
  VecWAXPY(d, -1.0, a, b);
  PetscReal nd, na;
  VecNorm(d, NORM_INFINITY, &nd);
  VecNorm(a, NORM_INFINITY, &na);
  return nd / na;
}

// The thick sphere on P1 at nu = 0.4999 (kappa / mu = 5,000), deformed by a few percent.
struct NearlyIncompressibleSphere {
  hs::Config config;
  hs::Distribution dist;
  NearlyIncompressibleSphere() {
    config = hs::parse_deck(kSource + "/input/lame_sphere.yaml",
                            {"mesh.parameters.h=0.5", "mesh.order=1", "materials[0].density=1000"});
    config.materials[0].law = hs::make_material_law("neo_hookean", {{"E", 1e6}, {"nu", 0.4999}});
    config.materials[0].element = hs::ElementFormulation::nodal_pressure;
    dist = hs::load_distributed_mesh(config.mesh, PETSC_COMM_WORLD);
  }
};

void expect_same_solutions(Mat J, const std::string& what) {
  const hs::KspHandle assembled = direct_solver(J, PCCHOLESKY);
  const hs::KspHandle mixed = direct_solver(J, hs::kMixedFactorType);
  std::vector<hs::VecHandle> b(3), x(3), y(3);
  for (int j = 0; j < 3; ++j) {
    for (auto* v : {&b[j], &x[j], &y[j]}) MatCreateVecs(J, nullptr, v->out());
    fill_random(b[j], 1.0, 10 + j);
  }
  KSPSolve(assembled, b[0], x[0]);
  KSPSolve(mixed, b[0], y[0]);
  KSPConvergedReason reason;
  KSPGetConvergedReason(mixed, &reason);
  EXPECT_GE(reason, 0) << what;
  EXPECT_LT(relative_difference(x[0], y[0]), 1e-8) << what;

  // Several columns at once (PCMatApply through the mixed factors), as the controller does.
  std::vector<Vec> bs, xs, ys;
  for (int j = 0; j < 3; ++j) {
    bs.push_back(b[j]);
    xs.push_back(x[j]);
    ys.push_back(y[j]);
  }
  ASSERT_TRUE(hs::solve_columns(assembled, bs, xs));
  ASSERT_TRUE(hs::solve_columns(mixed, bs, ys));
  for (int j = 0; j < 3; ++j) EXPECT_LT(relative_difference(xs[j], ys[j]), 1e-8) << what << j;

  // Both factorizations count J's negative eigenvalues alike.
  PC pc;
  Mat F;
  PetscInt negative = -1;
  KSPGetPC(assembled, &pc);
  PCFactorGetMatrix(pc, &F);
  MatMumpsGetInfog(F, 12, &negative);
  KSPGetPC(mixed, &pc);
  EXPECT_EQ(hs::mixed_factor_negative_pivots(pc), negative) << what;
}

TEST(MixedFactor, SolvesTheAssembledTangent) {
  NearlyIncompressibleSphere f;
  hs::Problem problem(f.config, f.dist, PETSC_COMM_WORLD);
  ASSERT_TRUE(problem.has_nodal_pressure());
  const hs::VecHandle u(problem.create_vector());
  fill_random(u, 0.01, 3);
  problem.apply_dirichlet(u, 0.7);
  const hs::MatHandle J(problem.create_matrix(true));
  ASSERT_TRUE(problem.jacobian(u, 0.7, J));
  expect_same_solutions(J, "static");

  // A time step's tangent K + c M: the mixed system carries c M in its displacement block.
  hs::InertiaTerm inertia;
  inertia.M = hs::MatHandle(problem.create_mass_matrix());
  inertia.c = 4e6;  // 4 / dt^2 at dt = 1 ms (Newmark's trapezoidal rule)
  problem.set_inertia(&inertia);
  ASSERT_TRUE(problem.jacobian(u, 0.7, J));
  problem.set_inertia(nullptr);
  expect_same_solutions(J, "with inertia");
}

// J = K + G^T D G with K = diag(2, -9, 3, 4), G = [1 1 0 0; 0 0 1 1], D = diag(5, 7): J's
// blocks [7 5; 5 -4] and [10 7; 7 11] have determinants -53 and 61, so J has one negative
// eigenvalue; the mixed system [K G^T; G -D^-1] has three.
TEST(MixedFactor, CountsTheTangentsNegativeEigenvalues) {
  hs::MatHandle J, A;
  const double Jv[4][4] = {{7, 5, 0, 0}, {5, -4, 0, 0}, {0, 0, 10, 7}, {0, 0, 7, 11}};
  MatCreateSeqDense(PETSC_COMM_SELF, 4, 4, nullptr, J.out());
  MatCreateSeqDense(PETSC_COMM_SELF, 6, 6, nullptr, A.out());
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) MatSetValue(J, i, j, Jv[i][j], INSERT_VALUES);
  const double K[4] = {2, -9, 3, 4}, D[2] = {5, 7};
  for (int i = 0; i < 4; ++i) {
    MatSetValue(A, i, i, K[i], INSERT_VALUES);
    MatSetValue(A, i, 4 + i / 2, 1.0, INSERT_VALUES);
    MatSetValue(A, 4 + i / 2, i, 1.0, INSERT_VALUES);
  }
  for (int a = 0; a < 2; ++a) MatSetValue(A, 4 + a, 4 + a, -1.0 / D[a], INSERT_VALUES);
  for (Mat M : {J.get(), A.get()}) {
    MatAssemblyBegin(M, MAT_FINAL_ASSEMBLY);
    MatAssemblyEnd(M, MAT_FINAL_ASSEMBLY);
  }
  hs::MatHandle Jaij, Aaij;  // MUMPS factors AIJ matrices
  MatConvert(J, MATAIJ, MAT_INITIAL_MATRIX, Jaij.out());
  MatConvert(A, MATAIJ, MAT_INITIAL_MATRIX, Aaij.out());
  PetscObjectCompose(reinterpret_cast<PetscObject>(Jaij.get()), hs::kMixedTangentKey,
                     reinterpret_cast<PetscObject>(Aaij.get()));
  const hs::KspHandle mixed = direct_solver(Jaij, hs::kMixedFactorType);
  PC pc;
  KSPGetPC(mixed, &pc);
  EXPECT_EQ(hs::mixed_factor_negative_pivots(pc), 1);

  // J x = b solved exactly: x = (1, 2, 3, 4) from b = J x.
  hs::VecHandle x, b, y;
  MatCreateVecs(Jaij, x.out(), b.out());
  VecDuplicate(x, y.out());
  for (int i = 0; i < 4; ++i) VecSetValue(x, i, i + 1.0, INSERT_VALUES);
  VecAssemblyBegin(x);
  VecAssemblyEnd(x);
  MatMult(Jaij, x, b);
  KSPSolve(mixed, b, y);
  EXPECT_LT(relative_difference(x, y), 1e-14);
}

TEST(MixedFactor, RefusesATangentWithoutNodalPressures) {
  hs::MatHandle J;
  MatCreateAIJ(PETSC_COMM_SELF, 2, 2, 2, 2, 1, nullptr, 0, nullptr, J.out());
  for (int i = 0; i < 2; ++i) MatSetValue(J, i, i, 1.0, INSERT_VALUES);
  MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY);
  MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY);
  hs::register_mixed_factor();
  hs::KspHandle ksp;
  KSPCreate(PETSC_COMM_SELF, ksp.out());
  KSPSetOperators(ksp, J, J);
  KSPSetType(ksp, KSPPREONLY);
  PC pc;
  KSPGetPC(ksp, &pc);
  PCSetType(pc, hs::kMixedFactorType);
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  const PetscErrorCode code = KSPSetUp(ksp);
  PetscPopErrorHandler();
  EXPECT_EQ(code, PETSC_ERR_ARG_WRONG);
}

// OpenBLAS at several threads is set to one where no variable says how many; where one
// does, it is left as that says.
TEST(BlasThreads, OneOpenBlasThreadUnlessTheUserChose) {
  using Get = int (*)();
  using Set = void (*)(int);
  const auto get = reinterpret_cast<Get>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  const auto set = reinterpret_cast<Set>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  if (!get || !set) GTEST_SKIP() << "the BLAS is not OpenBLAS";
  const char* names[] = {"OPENBLAS_NUM_THREADS", "GOTO_NUM_THREADS", "OMP_NUM_THREADS"};
  std::vector<std::pair<std::string, std::string>> saved;
  for (const char* name : names)
    if (const char* value = std::getenv(name)) saved.emplace_back(name, value);
  for (const char* name : names) unsetenv(name);

  setenv("OMP_NUM_THREADS", "2", 1);
  set(2);
  const int before = get();  // 2, or fewer on a machine of one core
  EXPECT_EQ(hs::limit_blas_threads(), "as OMP_NUM_THREADS=2 sets them");
  EXPECT_EQ(get(), before);
  unsetenv("OMP_NUM_THREADS");
  EXPECT_EQ(hs::limit_blas_threads().rfind("1 (OpenBLAS", 0), 0u);
  EXPECT_EQ(get(), 1);

  for (const auto& [name, value] : saved) setenv(name.c_str(), value.c_str(), 1);
  set(1);
}

}  // namespace mpi_test_mixed_factor
}  // namespace
