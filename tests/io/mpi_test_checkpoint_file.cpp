// checkpoint.h5 written by every rank and read back (src/io/checkpoint_file.hpp): a state of
// over 200 KB of JSON (a long control run's results so far: past the 64 KB that HDF5's original
// format allows an attribute), the rows of a field by node id, a series and an element field
// by element id; a state that
// differs between ranks; and a checkpoint that finds no room.
#include <gtest/gtest.h>
#include <mpi.h>

#include <filesystem>

#include "../mpi_test_folder.hpp"
#include "common/error.hpp"
#include "file_size_limit.hpp"
#include "io/checkpoint_file.hpp"

namespace {

TEST(CheckpointFile, AStateOfHundredsOfKilobytesAndTheRowsOfEveryRank) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  nlohmann::json state;
  state["targets"] = nlohmann::json::array();
  for (int k = 0; k < 6000; ++k)
    state["targets"].push_back({{"set", k}, {"reached", {0.09, 1e-3 * k, -0.012}}});
  ASSERT_GT(state.dump().size(), 200000u);
  // 4 nodes per rank, numbered backwards in the file so that the ids are not the rows.
  const int64_t nodes = 4 * size;
  hs::CheckpointRows rows;
  rows.nodes = nodes;
  rows.first = 4 * rank;
  std::vector<double> values;
  for (int64_t i = 0; i < 4; ++i) {
    const int64_t id = nodes - 1 - (rows.first + i);
    rows.node_ids.push_back(id);
    for (int c = 0; c < 3; ++c) values.push_back(10.0 * id + c);
  }
  // Elements: rank r has r + 1 of them, numbered backwards in the file too.
  rows.elements = size * (size + 1) / 2;
  rows.first_element = rank * (rank + 1) / 2;
  std::vector<double> multipliers;
  for (int64_t i = 0; i <= rank; ++i) {
    rows.element_ids.push_back(rows.elements - 1 - (rows.first_element + i));
    multipliers.push_back(-0.5 * rows.element_ids.back());
  }
  const std::string path = (hs_test::test_folder() / "checkpoint.h5").string();
  const std::vector<double> energy =
      rank == 0 ? std::vector<double>{1.5, 2.5} : std::vector<double>{};
  hs::write_checkpoint(path, MPI_COMM_WORLD, state, rows, {{"displacement", values}},
                       {{"energy", energy}}, {{"lambda", multipliers}});

  const hs::CheckpointFile file(path);
  EXPECT_EQ(file.state(), state);
  EXPECT_EQ(file.nodes(), nodes);
  const auto ids = file.node_ids(0, nodes);
  const auto u = file.field("displacement", 0, nodes);
  ASSERT_EQ(ids.size(), static_cast<size_t>(nodes));
  for (int64_t r = 0; r < nodes; ++r) {
    EXPECT_EQ(ids[r], nodes - 1 - r);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(u[3 * r + c], 10.0 * ids[r] + c);
  }
  EXPECT_EQ(file.series("energy"), (std::vector<double>{1.5, 2.5}));
  ASSERT_EQ(file.elements(), rows.elements);
  EXPECT_TRUE(file.has_element_field("lambda"));
  EXPECT_FALSE(file.has_element_field("pressure"));
  const auto element_ids = file.element_ids(0, rows.elements);
  const auto lambda = file.element_field("lambda", 0, rows.elements);
  for (int64_t r = 0; r < rows.elements; ++r) {
    EXPECT_EQ(element_ids[r], rows.elements - 1 - r);
    EXPECT_EQ(lambda[r], -0.5 * element_ids[r]);
  }
}

// A state whose text differs between ranks (a time each rank measured itself, with a number
// of digits of its own) is written as rank 0's, and every rank returns. Before, the attribute's
// lengths differed and the ranks waited on each other in HDF5's close for ever.
TEST(CheckpointFile, AStateThatDiffersBetweenRanksIsRankZerosAndWritten) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const nlohmann::json state = {{"answer_ms", rank == 0 ? 12.5 : 123.456789012345}};
  hs::CheckpointRows rows;
  rows.nodes = size;  // one node per rank
  rows.first = rank;
  rows.node_ids = {rank};
  const std::string path = (hs_test::test_folder() / "differing.h5").string();
  hs::write_checkpoint(path, MPI_COMM_WORLD, state, rows, {}, {});
  const hs::CheckpointFile file(path);
  EXPECT_EQ(file.state()["answer_ms"].get<double>(), 12.5);
}

// A checkpoint that finds no room (a file size limit here, a full disk in a run) stops every
// rank together with the file and the reason, leaves no .tmp behind and the previous
// checkpoint whole. Before: HDF5's error stack printed, std::runtime_error, the .tmp left.
TEST(CheckpointFile, OneThatFindsNoRoomStopsEveryRankAndLeavesThePreviousOne) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  hs::CheckpointRows rows;
  rows.nodes = 1000 * size;
  rows.first = 1000 * rank;
  std::vector<double> values;
  for (int64_t i = 0; i < 1000; ++i) {
    rows.node_ids.push_back(rows.first + i);
    for (int c = 0; c < 3; ++c) values.push_back(1.0 * i + c);
  }
  const std::string path = (hs_test::test_folder() / "checkpoint.h5").string();
  hs::write_checkpoint(path, MPI_COMM_WORLD, {{"step", 1}}, rows, {{"displacement", values}}, {});
  const auto before = std::filesystem::file_size(path);
  std::string message;
  {
    const hs::testing::FileSizeLimit limit(before / 2);
    try {
      hs::write_checkpoint(path, MPI_COMM_WORLD, {{"step", 2}}, rows,
                           {{"displacement", values}, {"velocity", values}}, {});
    } catch (const hs::SolveError& e) {
      message = e.what();
    }
  }
  // On every rank: "checkpoint not written: <path>.tmp: no room for N KB more: File too large".
  EXPECT_EQ(message.find("checkpoint not written: " + path + ".tmp: no room for "), 0u) << message;
  EXPECT_NE(message.find(" KB more: File too large"), std::string::npos) << message;
  MPI_Barrier(MPI_COMM_WORLD);
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
  const hs::CheckpointFile file(path);
  EXPECT_EQ(file.state()["step"], 1);
  EXPECT_EQ(file.field("displacement", 0, rows.nodes)[3 * 999 + 2], 999.0 + 2);
}

}  // namespace
