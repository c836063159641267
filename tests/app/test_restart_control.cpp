// Checkpoints and --restart of a batch control run (docs/control.md, "Checkpoints and
// restarts"): the hydraulic finger's run (three of its targets) killed (SIGKILL) after a checkpoint
// of its target sets and restarted on 1 rank, and stopped (SIGTERM) and restarted on 2, ends with
// the uninterrupted run's `targets` (target, saturation; reached position and actuation to the
// tolerances below) and final displacements: with the free configuration converged by Newton,
// with the one_step controller keeping its factorization across steps (made again at the
// restart), and with the factorizations in the background (a restart factors in line first;
// the corrections then differ by GMRES's tolerance). The interactive mode refuses both.
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <map>
#include <nlohmann/json.hpp>
#include <thread>

#include "../deck/temp_folder.hpp"
#include "../pinned_decks.hpp"
#include "restart_test_util.hpp"

namespace {
namespace test_restart_control {

namespace fs = std::filesystem;
using namespace hs::testing;

const std::string kSource = HYDROSOFT_SOURCE_DIR;

struct Case {
  std::string name, args;
  double reached_m, actuation_pa, displacement;  // tolerances against the uninterrupted run
};

std::ostream& operator<<(std::ostream& out, const Case& c) { return out << c.name; }

// Three targets a run: the deck's first (within reach), its second (above the finger's
// reach: the actuator held at its 30 kPa bound) and one reached again on the way down. A
// checkpoint after the first leaves two target sets to restart.
constexpr int kTargetSets = 3;

// The controllers' cases on a coarser mesh (847 nodes, not the deck's 1,961): what they check
// is that a restart continues the run, not the finger's figures. Their signals go to the
// process itself and land within milliseconds, well inside the target sets left. Their third
// target is -8 mm: on this mesh the deck's -17.5 mm, taken from 30 kPa, passes tangents that
// are not positive definite, and the background mode's uninterrupted runs then differed by
// 10 kPa (which factorization a step finds finished decided it); with -8 mm four runs agreed.
const std::string kCoarse =
    "--set mesh.parameters.h=0.004 --set 'control.targets=[{tip: [0.09, 0, -0.012]}, "
    "{tip: [0.09, 0, -0.003]}, {tip: [0.09, 0, -0.008]}]' ";

// Tolerances: a restart on the same ranks repeats the arithmetic; on 2 ranks the sums and
// the factorization go in another order (round-off of the solves, ~1e-12 relative).
const Case kNewton{"newton", kCoarse + "--set control.steps_per_target=4", 1e-10, 1e-4, 1e-8};
const Case kKeptFactorization{
    "kept_factorization",
    kCoarse +
        "--set control.free_solve=one_step --set control.refactor_every=4 "
        "--set control.steps_per_target=6",
    1e-10, 1e-4, 1e-8};
// The background mode is not repeatable even uninterrupted (which factorization a step finds
// finished depends on the threads' timing; two runs differed by 0.55 um and 0.39 Pa), and a
// restart's first step factors in line: its corrections differ by GMRES's tolerance (1e-5
// relative on each right-hand side), measured 1.7 to 2.8 um and 1.0 to 1.7 Pa (the deck's mesh).
const Case kBackground{"background",
                       kCoarse +
                           "--set control.free_solve=one_step --set control.factor_threads=1 "
                           "--set control.steps_per_target=6",
                       1e-5, 10.0, 1e-3};

// The job stopped through mpiexec (RestartControlRanks) runs on the deck's mesh to the deck's
// -17.5 mm: mpiexec passes a SIGTERM on a second after it gets it, and on the coarser mesh the
// 2-rank run had ended by then. Here the two target sets after the first checkpoint take about
// 5 s on 2 ranks: a signal test needs a run that outlasts it.
const Case kNewtonDeckMesh{"newton_deck_mesh",
                           "--set 'control.targets=[{tip: [0.09, 0, -0.012]}, "
                           "{tip: [0.09, 0, -0.003]}, {tip: [0.09, 0, -0.0175]}]' "
                           "--set control.steps_per_target=4",
                           1e-10, 1e-4, 1e-8};

// The hydraulic finger in its compressible material (../pinned_decks.hpp).
const std::string kDeck = "/input/finger_hydraulic.yaml -q " + hs_test::compressible_finger_args();

std::string command(const Case& c, const std::string& folder, const std::string& extra,
                    const std::string& err) {
  return std::string(HYDROSOFT_EXE) + " " + kSource + kDeck + c.args +
         " --set output.folder=" + folder + " " + extra + " > /dev/null 2>> " + err;
}

const std::string kCheckpoints = "--set 'output.checkpoint={every: 1}'";

// Waits (at most 120 s) for a checkpoint of the target sets (not of the rest state before).
bool wait_for_target_set_checkpoint(const std::string& path) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (std::chrono::steady_clock::now() < deadline) {
    if (fs::exists(path)) {
      const nlohmann::json s = checkpoint_state(path);
      if (s.is_object() && s["position"].contains("target_set")) return true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return false;
}

struct Difference {
  double reached_m = 0, actuation_pa = 0;
};

// Entry by entry: the same targets and saturations; the largest differences of the reached
// positions and the actuations.
Difference compare_targets(const nlohmann::json& expected, const nlohmann::json& got) {
  Difference d;
  EXPECT_EQ(got.size(), expected.size());
  for (size_t i = 0; i < std::min(got.size(), expected.size()); ++i) {
    const auto &e = expected[i], &g = got[i];
    EXPECT_EQ(g["target"], e["target"]) << i;
    EXPECT_EQ(g["saturated"], e["saturated"]) << i;
    EXPECT_EQ(g["limit_point"], e["limit_point"]) << i;
    for (int k = 0; k < 3; ++k)
      d.reached_m = std::max(
          d.reached_m, std::abs(g["reached"][k].get<double>() - e["reached"][k].get<double>()));
    for (size_t a = 0; a < e["actuation"].size(); ++a)
      d.actuation_pa = std::max(d.actuation_pa, std::abs(g["actuation"][a].get<double>() -
                                                         e["actuation"][a].get<double>()));
  }
  return d;
}

nlohmann::json summary_of(const std::string& folder) {
  return nlohmann::json::parse(text_of(folder + "/summary.json"));
}

// The uninterrupted run of a case (its summary and last displacements), made once and kept
// for every test that compares with it: the newton case's serves two.
struct Reference {
  bool ran = false;
  std::string error;  // its standard error when it failed
  nlohmann::json summary;
  LastStep u;
};

const Reference& reference_of(const Case& c) {
  static std::map<std::string, Reference> made;
  const auto found = made.find(c.name);
  if (found != made.end()) return found->second;
  TempFolder tmp;
  const std::string err = (tmp.path() / "err").string(), ref = (tmp.path() / "ref").string();
  Reference r;
  r.ran = run(command(c, ref, "", err)) == 0;
  if (r.ran) {
    r.summary = summary_of(ref);
    r.u = last_step(ref + "/finger_hydraulic.h5");
  } else {
    r.error = text_of(err);
  }
  return made.emplace(c.name, std::move(r)).first->second;
}

class RestartControl : public ::testing::TestWithParam<Case> {};

TEST_P(RestartControl, AfterSigkillOrSigtermEndsWithTheTargetsOfAnUninterruptedRun) {
  const Case& c = GetParam();
  TempFolder tmp;
  const std::string err = (tmp.path() / "err").string();
  const std::string killed = (tmp.path() / "killed").string(),
                    stopped = (tmp.path() / "stopped").string(),
                    two = (tmp.path() / "two").string();
  const std::string h5 = "/finger_hydraulic.h5";
  const Reference& reference = reference_of(c);
  ASSERT_TRUE(reference.ran) << reference.error;
  const nlohmann::json& expected = reference.summary;
  const LastStep& expected_u = reference.u;
  ASSERT_EQ(expected["targets"].size(), static_cast<size_t>(kTargetSets));

  // SIGKILL once a target set's checkpoint is there; restarted on 1 rank from the staging
  // folder the kill left, into the same output folder.
  pid_t pid = start(command(c, killed, kCheckpoints, err));
  ASSERT_TRUE(wait_for_target_set_checkpoint(killed + ".partial/checkpoint.h5")) << text_of(err);
  ASSERT_EQ(kill(pid, SIGKILL), 0);
  EXPECT_EQ(wait_for(pid), -1);
  ASSERT_EQ(run(command(c, killed, "--restart " + killed + ".partial", err)), 0) << text_of(err);
  const nlohmann::json once = summary_of(killed);
  EXPECT_EQ(once["status"], "ok");
  const int from = once["restarted_from"]["position"]["target_set"];
  EXPECT_GE(from, 1);
  EXPECT_LT(from, kTargetSets);
  EXPECT_EQ(once["outputs"].get<int>(), kTargetSets - from);  // the remaining target sets only
  EXPECT_TRUE(once["targets"][0]["step"].is_null());
  EXPECT_EQ(once["targets"][kTargetSets - 1]["step"], kTargetSets - 1 - from);
  EXPECT_EQ(once["step_time_ms"]["steps"], expected["step_time_ms"]["steps"]);
  const Difference d1 = compare_targets(expected["targets"], once["targets"]);
  EXPECT_LE(d1.reached_m, c.reached_m);
  EXPECT_LE(d1.actuation_pa, c.actuation_pa);
  const LastStep u1 = last_step(killed + h5);
  EXPECT_EQ(u1.time, expected_u.time);
  const double du1 = relative_difference(expected_u.u, u1.u);
  EXPECT_GE(du1, 0);
  EXPECT_LE(du1, c.displacement);

  // SIGTERM after a target set's checkpoint: the run stops at the next boundary, writing one
  // there into .failed; restarted on 2 ranks.
  pid = start(command(c, stopped, kCheckpoints, err));
  ASSERT_TRUE(wait_for_target_set_checkpoint(stopped + ".partial/checkpoint.h5")) << text_of(err);
  ASSERT_EQ(kill(pid, SIGTERM), 0);
  ASSERT_EQ(wait_for(pid), 143) << text_of(err);
  ASSERT_TRUE(
      checkpoint_state(stopped + ".failed/checkpoint.h5")["position"].contains("target_set"));
  // The stopped run's summary keeps the entries of the target sets it finished.
  const nlohmann::json stopped_summary = summary_of(stopped + ".failed");
  EXPECT_EQ(stopped_summary["status"], "failed");
  const int finished =
      checkpoint_state(stopped + ".failed/checkpoint.h5")["position"]["target_set"];
  ASSERT_EQ(stopped_summary["targets"].size(), static_cast<size_t>(finished));
  const Difference d0 = compare_targets(
      nlohmann::json(expected["targets"].begin(), expected["targets"].begin() + finished),
      stopped_summary["targets"]);
  EXPECT_LE(d0.reached_m, c.reached_m);
  ASSERT_EQ(run(std::string(HYDROSOFT_MPIEXEC) + " -np 2 " +
                command(c, two, "--restart " + stopped + ".failed", err)),
            0)
      << text_of(err);
  const nlohmann::json twice = summary_of(two);
  EXPECT_EQ(twice["restarted_from"]["ranks"], 1);
  const Difference d2 = compare_targets(expected["targets"], twice["targets"]);
  EXPECT_LE(d2.reached_m, c.reached_m);
  EXPECT_LE(d2.actuation_pa, c.actuation_pa);
  // The background case restarted on 2 ranks: some of its steps ran on a factorization
  // made in the background (on rank 0), not all in line.
  if (c.name == kBackground.name) {
    int stale = 0;
    for (const auto& k : twice["background_factorization"]["staleness"]) stale += k.get<int>() > 0;
    EXPECT_GT(stale, 0);
  }
  const LastStep u2 = last_step(two + h5);
  EXPECT_EQ(u2.time, expected_u.time);
  const double du2 = relative_difference(expected_u.u, u2.u);
  EXPECT_GE(du2, 0);
  EXPECT_LE(du2, c.displacement);
  std::cout << "[ restart  ] " << c.name << ": 1 rank after SIGKILL at target set " << from
            << ": reached " << d1.reached_m << " m, actuation " << d1.actuation_pa
            << " Pa, max |du| / max |u| " << du1 << "; 2 ranks after SIGTERM at target set "
            << twice["restarted_from"]["position"]["target_set"] << ": " << d2.reached_m << " m, "
            << d2.actuation_pa << " Pa, " << du2 << std::endl;
}

INSTANTIATE_TEST_SUITE_P(Controllers, RestartControl,
                         ::testing::Values(kNewton, kKeptFactorization, kBackground),
                         [](const auto& info) { return info.param.name; });

// A checkpoint written on 2 ranks, as a cluster's job would leave it: the job is stopped by
// SIGTERM to mpiexec (which passes it on, then kills what is left after a grace period), and
// its checkpoint restarted on 2 ranks and on 1 ends with the uninterrupted run's targets.
TEST(RestartControlRanks, ACheckpointWrittenOnTwoRanksRestartsOnTwoAndOnOne) {
  const Case& c = kNewtonDeckMesh;
  TempFolder tmp;
  const std::string err = (tmp.path() / "err").string();
  const std::string job = (tmp.path() / "job").string();
  const std::string mpiexec = std::string(HYDROSOFT_MPIEXEC) + " -np 2 ";
  const Reference& reference = reference_of(c);
  ASSERT_TRUE(reference.ran) << reference.error;
  const nlohmann::json& expected = reference.summary;

  const pid_t pid = start(mpiexec + command(c, job, kCheckpoints, err));
  ASSERT_TRUE(wait_for_target_set_checkpoint(job + ".partial/checkpoint.h5")) << text_of(err);
  ASSERT_EQ(kill(pid, SIGTERM), 0);
  EXPECT_NE(wait_for(pid), 0);
  // Stopped at a step boundary, its checkpoint is in .failed; killed first, in .partial.
  const std::string from =
      fs::exists(job + ".failed/checkpoint.h5") ? job + ".failed" : job + ".partial";
  ASSERT_EQ(checkpoint_state(from + "/checkpoint.h5")["ranks"], 2) << from;
  for (const int ranks : {2, 1}) {
    const std::string out = (tmp.path() / ("on" + std::to_string(ranks))).string();
    ASSERT_EQ(run((ranks == 2 ? mpiexec : "") + command(c, out, "--restart " + from, err)), 0)
        << text_of(err);
    const nlohmann::json got = summary_of(out);
    EXPECT_EQ(got["restarted_from"]["ranks"], 2);
    const Difference d = compare_targets(expected["targets"], got["targets"]);
    EXPECT_LE(d.reached_m, c.reached_m) << ranks << " ranks";
    EXPECT_LE(d.actuation_pa, c.actuation_pa) << ranks << " ranks";
    std::cout << "[ restart  ] 2-rank checkpoint (" << fs::path(from).extension().string()
              << ") at target set " << got["restarted_from"]["position"]["target_set"] << " on "
              << ranks << " ranks: reached " << d.reached_m << " m, actuation " << d.actuation_pa
              << " Pa" << std::endl;
  }
}

TEST(RestartControlRefused, TheInteractiveModeAndFrozenWeightsInOneStep) {
  TempFolder tmp;
  const std::string err = (tmp.path() / "err").string(), out = (tmp.path() / "out").string();
  const std::string deck =
      std::string(HYDROSOFT_EXE) + " " + kSource + kDeck + "--set output.folder=" + out + " ";
  EXPECT_EQ(
      run("echo '0.09 0 -0.01' | " + deck + kCheckpoints + " --targets - > /dev/null 2> " + err),
      2);
  EXPECT_NE(text_of(err).find("finger_hydraulic.yaml: output.checkpoint: not supported with "
                              "--targets - (an interactive session's targets come from its client"),
            std::string::npos)
      << text_of(err);
  EXPECT_EQ(run("echo '0.09 0 -0.01' | " + deck + "--restart " + out +
                " --targets - > /dev/null 2> " + err),
            2);
  EXPECT_NE(text_of(err).find("--restart: not supported with --targets -"), std::string::npos)
      << text_of(err);
  EXPECT_FALSE(fs::exists(out + ".partial"));
  EXPECT_EQ(run(deck + kCheckpoints +
                " --set control.free_solve=one_step "
                "--set cavities[0].fluid_weight.coupling=linearized > /dev/null 2> " +
                err),
            2);
  EXPECT_NE(text_of(err).find("output.checkpoint: not supported with control.free_solve one_step "
                              "and a hydraulic cavity's fluid_weight.coupling linearized"),
            std::string::npos)
      << text_of(err);
}

}  // namespace test_restart_control
}  // namespace
