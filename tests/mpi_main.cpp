// main() for MPI GoogleTest executables: PETSc (and so MPI) is initialised once,
// only rank 0 prints, so that the output of 2 ranks stays readable, and each test gets a
// private folder for its files, removed when it ends (mpi_test_folder.hpp).
#include <gtest/gtest.h>
#include <petscsys.h>

#include "mpi_test_folder.hpp"
#include "solvers/distributed_mesh.hpp"

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  hs::use_one_scotch_thread();
  PetscInitialize(&argc, &argv, nullptr, nullptr);
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank != 0) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  ::testing::UnitTest::GetInstance()->listeners().Append(new hs_test::TestFolderListener);
  int result = RUN_ALL_TESTS();
  // Every rank must agree on the verdict; a failure on any rank fails the test.
  int global = 0;
  MPI_Allreduce(&result, &global, 1, MPI_INT, MPI_MAX, PETSC_COMM_WORLD);
  PetscFinalize();
  return global;
}
