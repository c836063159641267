// A private folder for the files of each test of an MPI test executable, under the system's
// temporary folder: made (rank 0) when the test starts and removed with everything in it
// when the test ends, passed or failed, by the listener that tests/mpi_main.cpp installs.
// ctest runs the 1- and 2-rank variants and other executables at once; mkdtemp gives each
// test a folder no other process uses, and nothing is left behind in /tmp.
#pragma once

#include <gtest/gtest.h>
#include <mpi.h>
#include <stdlib.h>

#include <filesystem>
#include <iostream>
#include <string>

namespace hs_test {

namespace detail {
inline std::filesystem::path& current_test_folder() {
  static std::filesystem::path folder;
  return folder;
}
}  // namespace detail

// The running test's folder (the same path on every rank). Collective-free, so that a
// test may call it on rank 0 alone.
inline const std::filesystem::path& test_folder() {
  if (detail::current_test_folder().empty()) {
    std::cerr << "test_folder() called outside a test of an MPI test executable" << std::endl;
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
  return detail::current_test_folder();
}

// Makes each test's folder before it starts and removes it when it ends (collective: every
// rank runs every test, in the same order).
class TestFolderListener : public ::testing::EmptyTestEventListener {
 public:
  void OnTestStart(const ::testing::TestInfo&) override {
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    std::string path;
    if (rank == 0) {
      path = (std::filesystem::temp_directory_path() / "hydrosoft_test_XXXXXX").string();
      if (!mkdtemp(path.data())) {
        std::cerr << "mkdtemp failed for " << path << std::endl;
        MPI_Abort(MPI_COMM_WORLD, 1);
      }
    }
    int n = static_cast<int>(path.size());
    MPI_Bcast(&n, 1, MPI_INT, 0, MPI_COMM_WORLD);
    path.resize(n);
    MPI_Bcast(path.data(), n, MPI_CHAR, 0, MPI_COMM_WORLD);
    detail::current_test_folder() = path;
  }
  void OnTestEnd(const ::testing::TestInfo&) override {
    MPI_Barrier(MPI_COMM_WORLD);  // no rank still reads a file of the test
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    std::error_code ignored;
    if (rank == 0) std::filesystem::remove_all(detail::current_test_folder(), ignored);
    detail::current_test_folder().clear();
  }
};

}  // namespace hs_test
