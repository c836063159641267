// Checkpoints and --restart (docs/output.md, "Checkpoints and restarts"): a run killed
// (SIGKILL) or stopped (SIGTERM) after a checkpoint and restarted from it, on 1 rank and on
// 2, ends with the displacements of an uninterrupted run to 1e-8 relative: static load
// stepping, dynamics, and the states of a hydraulic cavity deck. A checkpoint of another deck
// or other deck values is refused before the output folder is touched.
#include <gtest/gtest.h>
#include <signal.h>

#include <nlohmann/json.hpp>

#include "../deck/temp_folder.hpp"
#include "restart_test_util.hpp"

namespace {

namespace fs = std::filesystem;
using namespace hs::testing;

const std::string kSource = HYDROSOFT_SOURCE_DIR;

struct Case {
  std::string name, deck, args;
};

std::ostream& operator<<(std::ostream& out, const Case& c) { return out << c.name; }

// Small and short, but long enough that a signal after the first checkpoint finds it going.
const Case kStatic{"static", "cantilever_gravity",
                   "--set mesh.order=1 --set materials[0].model=neo_hookean "
                   "--set materials[0].E=2e5 --set time.steps=20"};
const Case kDynamic{"dynamic", "cantilever_dynamic",
                    "--set mesh.order=1 --set time.end_time=2.0 --set output.every=1"};
const Case kStates{"states", "cylinder_water", "--set states[1].steps=20"};

std::string command(const Case& c, const std::string& folder, const std::string& extra,
                    const std::string& err) {
  return std::string(HYDROSOFT_EXE) + " " + kSource + "/input/" + c.deck + ".yaml -q " + c.args +
         " --set output.folder=" + folder + " " + extra + " > /dev/null 2>> " + err;
}

const std::string kCheckpoints = "--set 'output.checkpoint={every: 3}'";

class Restart : public ::testing::TestWithParam<Case> {};

TEST_P(Restart, AfterSigkillOrSigtermEndsAsAnUninterruptedRunOn1And2Ranks) {
  const Case& c = GetParam();
  TempFolder tmp;
  const std::string err = (tmp.path() / "err").string();
  const std::string ref = (tmp.path() / "ref").string(), run_folder = (tmp.path() / "run").string(),
                    stopped = (tmp.path() / "stopped").string(),
                    two = (tmp.path() / "two").string();
  const std::string h5 = "/" + c.deck + ".h5";
  ASSERT_EQ(run(command(c, ref, "", err)), 0) << text_of(err);
  const LastStep expected = last_step(ref + h5);
  ASSERT_GT(expected.steps, 0);

  // SIGKILL once the first checkpoint is there; restart from the staging folder the kill
  // left, into the same output folder (which clears that staging folder first).
  pid_t pid = start(command(c, run_folder, kCheckpoints, err));
  ASSERT_TRUE(wait_for_file(run_folder + ".partial/checkpoint.h5")) << text_of(err);
  ASSERT_EQ(kill(pid, SIGKILL), 0);
  EXPECT_EQ(wait_for(pid), -1);
  ASSERT_EQ(run(command(c, run_folder, "--restart " + run_folder + ".partial", err)), 0)
      << text_of(err);
  const LastStep once = last_step(run_folder + h5);
  EXPECT_EQ(once.time, expected.time);
  const double d1 = relative_difference(expected.u, once.u);
  EXPECT_GE(d1, 0);
  EXPECT_LT(d1, 1e-8);
  const auto summary = nlohmann::json::parse(text_of(run_folder + "/summary.json"));
  EXPECT_EQ(summary["status"], "ok");
  EXPECT_EQ(summary["restarted_from"]["folder"], run_folder + ".partial");
  // Where it went on from, without the results so far (they are the summary's own keys).
  for (const char* bulky : {"states", "verification", "constraints"})
    EXPECT_FALSE(summary["restarted_from"]["position"].contains(bulky)) << bulky;
  EXPECT_TRUE(summary["restarted_from"]["position"].contains("last"));
  EXPECT_LT(summary["outputs"].get<int>(), expected.steps);  // the remaining steps only

  // SIGTERM after a checkpoint: the stopped run writes one at its last step into .failed;
  // restarted from there on 2 ranks.
  pid = start(command(c, stopped, kCheckpoints, err));
  ASSERT_TRUE(wait_for_file(stopped + ".partial/checkpoint.h5")) << text_of(err);
  ASSERT_EQ(kill(pid, SIGTERM), 0);
  ASSERT_EQ(wait_for(pid), 143) << text_of(err);
  ASSERT_TRUE(fs::exists(stopped + ".failed/checkpoint.h5"));
  ASSERT_EQ(run(std::string(HYDROSOFT_MPIEXEC) + " -np 2 " +
                command(c, two, "--restart " + stopped + ".failed", err)),
            0)
      << text_of(err);
  const LastStep twice = last_step(two + h5);
  EXPECT_EQ(twice.time, expected.time);
  const double d2 = relative_difference(expected.u, twice.u);
  EXPECT_GE(d2, 0);
  EXPECT_LT(d2, 1e-8);
  std::cout << "[ restart  ] " << c.name << ": 1 rank after SIGKILL " << d1
            << ", 2 ranks after SIGTERM " << d2 << " (max |du| / max |u|)" << std::endl;
}

INSTANTIATE_TEST_SUITE_P(Decks, Restart, ::testing::Values(kStatic, kDynamic, kStates),
                         [](const auto& info) { return info.param.name; });

TEST(RestartRefused, ACheckpointOfAnotherDeckOrOtherValues) {
  TempFolder tmp;
  const std::string err = (tmp.path() / "err").string(), other = (tmp.path() / "other").string();
  const std::string folder = (tmp.path() / "static").string();
  Case few = kStatic;
  few.args += " --set time.steps=4";
  ASSERT_EQ(run(command(few, folder, kCheckpoints, err)), 0) << text_of(err);
  const std::string file = folder + "/checkpoint.h5";
  ASSERT_TRUE(fs::exists(file));

  // Another deck (states, not a static load stepping).
  fs::remove(err);
  EXPECT_EQ(run(command(kStates, other, "--restart " + folder, err)), 2);
  EXPECT_NE(text_of(err).find("--restart: " + file +
                              ": written by a static run, this deck runs "
                              "states"),
            std::string::npos)
      << text_of(err);
  EXPECT_FALSE(fs::exists(other));
  EXPECT_FALSE(fs::exists(other + ".partial"));

  // The same deck on another mesh (its size parameter): another configuration.
  fs::remove(err);
  Case finer = few;
  finer.args += " --set mesh.parameters.h=0.04";
  EXPECT_EQ(run(command(finer, other, "--restart " + folder, err)), 2);
  EXPECT_NE(text_of(err).find("--restart: " + file + ": written for another deck or other values"),
            std::string::npos)
      << text_of(err);

  // Output keys may differ: a checkpoint of step 3 of 4, continued with other output keys.
  fs::remove(err);
  EXPECT_EQ(run(command(few, other, "--set output.every=2 --restart " + folder, err)), 0)
      << text_of(err);

  // Not a checkpoint at all.
  fs::remove(err);
  EXPECT_EQ(run(command(few, other, "--restart " + folder + "/summary.json", err)), 2);
  EXPECT_NE(text_of(err).find("not an HDF5 file"), std::string::npos) << text_of(err);
}

}  // namespace
