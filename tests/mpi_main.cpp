// main() for MPI GoogleTest executables: PETSc (and so MPI) is initialised once; only rank 0
// prints in full (the others their failures), so that the output of 2 ranks stays readable;
// each test gets a private folder for its files, removed when it ends (mpi_test_folder.hpp).
#include <gtest/gtest.h>
#include <petscsys.h>

#include <cstdio>
#include <string>

#include "mpi_test_folder.hpp"
#include "solvers/distributed_mesh.hpp"

namespace {

// The other ranks print their failures only, each line marked with its rank: a failure there
// would otherwise fail the test without a word of what failed.
class FailurePrinter : public ::testing::EmptyTestEventListener {
 public:
  explicit FailurePrinter(int rank) : rank_(rank) {}
  void OnTestStart(const ::testing::TestInfo& test) override {
    test_ = std::string(test.test_suite_name()) + "." + test.name();
  }
  void OnTestPartResult(const ::testing::TestPartResult& result) override {
    if (!result.failed()) return;
    std::fprintf(stderr, "[rank %d] %s: %s:%d: %s\n", rank_, test_.c_str(),
                 result.file_name() ? result.file_name() : "", result.line_number(),
                 result.message());
  }

 private:
  int rank_;
  std::string test_;
};

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  hs::use_one_scotch_thread();
  PetscInitialize(&argc, &argv, nullptr, nullptr);
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank != 0) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
    listeners.Append(new FailurePrinter(rank));
  }
  ::testing::UnitTest::GetInstance()->listeners().Append(new hs_test::TestFolderListener);
  int result = RUN_ALL_TESTS();
  // Every rank must agree on the verdict; a failure on any rank fails the test.
  int global = 0;
  MPI_Allreduce(&result, &global, 1, MPI_INT, MPI_MAX, PETSC_COMM_WORLD);
  PetscFinalize();
  return global;
}
