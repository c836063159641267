// Runs and their output folders, on 1 and 2 ranks: a run on a folder that another run is
// writing stops before any work on every rank, with a message naming the folder, and
// leaves the other run's staging folder alone; and each test's files live in its own folder,
// removed when the test ends (../mpi_test_folder.hpp), so that the tests leave nothing in
// the temporary folder.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <thread>

#include "../solvers/run_deck.hpp"
#include "common/error.hpp"
#include "io/output.hpp"

namespace {
namespace mpi_test_output_folders {

namespace fs = std::filesystem;

// The smallest deck: one P2 block (a second or less on 2 ranks).
const char* kDeck = "hydrostatic_patch.yaml";

int world_rank() {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
}

TEST(OutputFolders, ARunOnAFolderThatAnotherRunIsWritingStopsAtOnce) {
  const std::string folder = hs_test::out_folder("shared");
  // Another run (on rank 0, like every run's output) holds the folder and has staged a file.
  std::unique_ptr<hs::OutputFolder> other;
  if (world_rank() == 0) {
    other = std::make_unique<hs::OutputFolder>(folder);
    std::ofstream(other->staging() + "/step.txt") << "the other run's";
  }
  std::string message;
  try {
    hs_test::run_deck(kDeck, {}, "shared");
  } catch (const hs::InputError& e) {
    message = e.what();
  }
  // Every rank stops with the same message (none waits in a collective for rank 0).
  EXPECT_NE(message.find("output folder '" + folder + "': another run is writing it"),
            std::string::npos)
      << message;
  if (world_rank() == 0) {
    std::ifstream staged(other->staging() + "/step.txt");
    std::string text;
    std::getline(staged, text);
    EXPECT_EQ(text, "the other run's");
    EXPECT_FALSE(fs::exists(folder));
    other.reset();  // the other run ends (fails): its lock goes with it
  }
  // Now the folder is free.
  const auto summary = hs_test::run_deck(kDeck, {}, "shared");
  EXPECT_EQ(summary["output"]["folder"], folder);
}

// A run on "<folder>.partial" used to replace the staging folder of the run on <folder>,
// which then failed while the other ended with status 0. Its name is refused, on every rank,
// before any work; the running one's staging folder is left alone.
TEST(OutputFolders, ARunOnAnotherRunsStagingFolderIsRefused) {
  const std::string folder = hs_test::out_folder("fa");
  std::unique_ptr<hs::OutputFolder> other;
  if (world_rank() == 0) {
    other = std::make_unique<hs::OutputFolder>(folder);
    std::ofstream(other->staging() + "/step.txt") << "the other run's";
  }
  std::string message;
  try {
    hs_test::run_deck(kDeck, {}, "fa.partial");
  } catch (const hs::InputError& e) {
    message = e.what();
  }
  EXPECT_NE(message.find("output.folder: a name ending in '.partial' is that of the staging "
                         "folder of '" +
                         folder + "'"),
            std::string::npos)
      << message;
  if (world_rank() == 0) {
    std::ifstream staged(other->staging() + "/step.txt");
    std::string text;
    std::getline(staged, text);
    EXPECT_EQ(text, "the other run's");
    EXPECT_FALSE(fs::exists(folder + ".partial.partial"));
    other->commit();
    EXPECT_TRUE(fs::exists(folder + "/step.txt"));
  }
}

// What the first test of the pair below wrote, for the second to look at.
fs::path written_by_the_previous_test;

// Each rank reads the deck itself, and reading it checks the output folder; rank 0 makes the
// staging folder (and its marker, which its check of a later rank looks for). A rank that
// reads the deck later than rank 0 starts its run must find no staging folder yet: one caught
// half made (no marker yet) stopped that rank alone and left the other waiting (seen as a
// hang of 2-rank tests under load).
TEST(OutputFolders, NoRankMakesTheStagingFolderBeforeEveryRankHasReadTheDeck) {
  const std::string folder = hs_test::out_folder("late_reader");
  const std::string deck = std::string(HYDROSOFT_SOURCE_DIR) + "/input/" + kDeck;
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  bool staged_before_reading = false;
  if (world_rank() == size - 1 && size > 1) {
    std::this_thread::sleep_for(std::chrono::milliseconds(500));  // rank 0 is in its run
    staged_before_reading = fs::exists(folder + ".partial");
  }
  const hs::Config config = hs::parse_deck(deck, {"output.folder=" + folder});
  hs::run_simulation(config, MPI_COMM_WORLD);
  EXPECT_FALSE(staged_before_reading);
  EXPECT_TRUE(fs::exists(folder + "/summary.json"));
}

TEST(TestFolders, ATestWritesItsOutputsIntoItsOwnFolder) {
  hs_test::run_deck(kDeck, {}, "mine");
  const fs::path out = hs_test::out_folder("mine");
  EXPECT_EQ(out.parent_path(), hs_test::test_folder());
  if (world_rank() == 0) EXPECT_TRUE(fs::exists(out / "summary.json"));
  written_by_the_previous_test = out;
}

TEST(TestFolders, AndTheFolderIsRemovedWhenTheTestEnds) {
  // Runs after the test above (GoogleTest keeps the order of a file unless shuffled).
  ASSERT_FALSE(written_by_the_previous_test.empty());
  EXPECT_FALSE(fs::exists(written_by_the_previous_test));
  EXPECT_FALSE(fs::exists(written_by_the_previous_test.parent_path()));
  EXPECT_NE(hs_test::test_folder(), written_by_the_previous_test.parent_path());
}

}  // namespace mpi_test_output_folders
}  // namespace
