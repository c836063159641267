// The executable's outcomes beyond success: a run that fails mid-way keeps its converged steps
// in "<folder>.failed" (an .h5 and .xmf with exactly those steps, summary.json saying why)
// and leaves an earlier good <folder> alone; SIGTERM stops a run at a step boundary with exit
// status 143, on 1 rank and on 2 under mpiexec, and in the interactive mode while it waits for
// a target line; history.csv and /history of the .h5 hold one
// row per output step, equal to summary.json's values; a run whose disk fills ends on every
// rank with one line naming the file, its converged steps (or its checkpoint) kept.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <hdf5.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <thread>

#include "../deck/temp_folder.hpp"
#include "../pinned_decks.hpp"
#include "child_process.hpp"
#include "text_file.hpp"

namespace {
namespace test_run_outcomes {

namespace fs = std::filesystem;
using hs::testing::TempFolder;

const std::string kSource = HYDROSOFT_SOURCE_DIR;

// The P1 cantilever of input/cantilever_gravity.yaml writing into `folder`, with `extra`.
std::string cantilever(const std::string& folder, const std::string& extra) {
  return std::string(HYDROSOFT_EXE) + " " + kSource +
         "/input/cantilever_gravity.yaml -q --set mesh.order=1 --set output.folder=" + folder +
         " " + extra;
}

// Load factors 0.01 and 0.02 converge; the jump to 100 with no cutback inverts an element
// of the soft neo-Hookean beam at step 3 of 5.
const std::string kFailsAtStep3 =
    "--set materials[0].model=neo_hookean --set materials[0].E=1e5 --set time.steps=5 "
    "--set time.schedule=[0.01,0.02,100,200,300] --set time.max_cutbacks=0";

using hs::testing::run;
using hs::testing::start;
using hs::testing::wait_for;

using hs::testing::text_of;

nlohmann::json json_of(const std::string& path) { return nlohmann::json::parse(text_of(path)); }

// history.csv: its header and its rows of numbers.
struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  size_t column(const std::string& name) const {
    for (size_t c = 0; c < header.size(); ++c)
      if (header[c] == name) return c;
    ADD_FAILURE() << "no column " << name;
    return 0;
  }
};

Csv csv_of(const std::string& path) {
  Csv csv;
  std::ifstream in(path);
  std::string line;
  auto split = [](const std::string& text) {
    std::vector<std::string> cells;
    std::stringstream s(text);
    for (std::string cell; std::getline(s, cell, ',');) cells.push_back(cell);
    return cells;
  };
  if (std::getline(in, line)) csv.header = split(line);
  while (std::getline(in, line)) {
    std::vector<double> row;
    for (const auto& cell : split(line)) row.push_back(std::stod(cell));
    EXPECT_EQ(row.size(), csv.header.size()) << line;
    csv.rows.push_back(row);
  }
  return csv;
}

// The names of the root's groups step_<k> of an .h5.
int h5_steps(const std::string& path) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  EXPECT_GE(file, 0) << path;
  int steps = 0;
  while (H5Lexists(file, ("/step_" + std::to_string(steps)).c_str(), H5P_DEFAULT) > 0) ++steps;
  H5Fclose(file);
  return steps;
}

// A 1D dataset of the .h5 read as doubles (empty if it is missing).
std::vector<double> h5_column(const std::string& path, const std::string& dataset) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  std::vector<double> values;
  if (H5Lexists(file, "/history", H5P_DEFAULT) > 0 &&
      H5Lexists(file, dataset.c_str(), H5P_DEFAULT) > 0) {
    const hid_t set = H5Dopen2(file, dataset.c_str(), H5P_DEFAULT);
    const hid_t space = H5Dget_space(set);
    values.resize(H5Sget_simple_extent_npoints(space));
    H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
    H5Sclose(space);
    H5Dclose(set);
  }
  H5Fclose(file);
  return values;
}

// The .xmf's Uniform grids, and whether it names a step_<k> for k >= steps.
int xmf_grids(const std::string& path) {
  const std::string xmf = text_of(path);
  int grids = 0;
  for (size_t at = xmf.find("GridType=\"Uniform\""); at != std::string::npos;
       at = xmf.find("GridType=\"Uniform\"", at + 1))
    ++grids;
  return grids;
}

bool xmf_names_step(const std::string& path, int k) {
  return text_of(path).find(":/step_" + std::to_string(k) + "/") != std::string::npos;
}

TEST(FailedRun, KeepsTheConvergedStepsBesideAnEarlierGoodResult) {
  TempFolder tmp;
  const std::string folder = (tmp.path() / "beam").string();
  ASSERT_EQ(run(cantilever(folder, "--set time.steps=2") + " 2> " + folder + ".err"), 0);
  const std::string good_summary = text_of(folder + "/summary.json");
  EXPECT_EQ(json_of(folder + "/summary.json")["status"], "ok");

  const std::string err = (tmp.path() / "failed.err").string();
  EXPECT_EQ(run(cantilever(folder, kFailsAtStep3) + " 2> " + err), 3) << text_of(err);
  // The good result is untouched; the failed run's two converged steps are beside it.
  EXPECT_EQ(text_of(folder + "/summary.json"), good_summary);
  EXPECT_EQ(h5_steps(folder + "/cantilever_gravity.h5"), 2);
  const std::string failed = folder + ".failed";
  ASSERT_TRUE(fs::is_directory(failed)) << text_of(err);
  EXPECT_FALSE(fs::exists(folder + ".partial"));
  EXPECT_FALSE(fs::exists(folder + ".lock"));
  EXPECT_EQ(h5_steps(failed + "/cantilever_gravity.h5"), 2);
  EXPECT_EQ(xmf_grids(failed + "/cantilever_gravity.xmf"), 2);
  EXPECT_TRUE(xmf_names_step(failed + "/cantilever_gravity.xmf", 1));
  EXPECT_FALSE(xmf_names_step(failed + "/cantilever_gravity.xmf", 2));
  const auto summary = json_of(failed + "/summary.json");
  EXPECT_EQ(summary["status"], "failed");
  EXPECT_NE(summary["reason"].get<std::string>().find("step 3 (load factor 100"), std::string::npos)
      << summary["reason"];
  EXPECT_NE(summary["reason"].get<std::string>().find("is inverted"), std::string::npos);
  EXPECT_EQ(summary["outputs"], 2);
  EXPECT_EQ(summary["last_converged"]["step"], 1);
  EXPECT_DOUBLE_EQ(summary["last_converged"]["load_factor"].get<double>(), 0.02);
  EXPECT_EQ(csv_of(failed + "/history.csv").rows.size(), 2u);
  // The message names the deck, says why, then where the steps are.
  EXPECT_NE(text_of(err).find("hydrosoft: error: " + kSource +
                              "/input/cantilever_gravity.yaml: step 3 (load factor 100"),
            std::string::npos)
      << text_of(err);
  EXPECT_NE(text_of(err).find("the 2 converged output steps are in " + failed), std::string::npos)
      << text_of(err);

  // A second failure replaces the first's folder; the good result still stands.
  EXPECT_EQ(run(cantilever(folder, kFailsAtStep3 + " --set time.schedule=[0.01,100,200,300,400]") +
                " 2> " + err),
            3);
  EXPECT_EQ(h5_steps(failed + "/cantilever_gravity.h5"), 1);
  EXPECT_EQ(json_of(failed + "/summary.json")["outputs"], 1);
  EXPECT_EQ(text_of(folder + "/summary.json"), good_summary);
}

// With output every 10 steps and a checkpoint every step, the failure at step 3 leaves no
// output step, only the checkpoint: the message said "the 0 converged output steps".
TEST(FailedRun, ACheckpointAloneIsSaidToBeOne) {
  TempFolder tmp;
  const std::string folder = (tmp.path() / "beam").string();
  const std::string err = (tmp.path() / "err").string();
  EXPECT_EQ(run(cantilever(folder, kFailsAtStep3 +
                                       " --set output.every=10 --set output.checkpoint.every=1") +
                " 2> " + err),
            3);
  EXPECT_NE(text_of(err).find("\n  a checkpoint to restart from is in " + folder +
                              ".failed/ (summary.json: \"status\": \"failed\")"),
            std::string::npos)
      << text_of(err);
  EXPECT_TRUE(fs::exists(folder + ".failed/checkpoint.h5"));
}

TEST(FailedRun, AFailureBeforeAnyStepLeavesNothing) {
  TempFolder tmp;
  const std::string folder = (tmp.path() / "beam").string();
  const std::string err = (tmp.path() / "err").string();
  // The first increment already inverts an element: no step converged.
  EXPECT_EQ(run(cantilever(folder, kFailsAtStep3 + " --set time.schedule=[100,200,300,400,500]") +
                " 2> " + err),
            3);
  EXPECT_NE(text_of(err).find("no step had converged: nothing was kept"), std::string::npos)
      << text_of(err);
  EXPECT_FALSE(fs::exists(folder + ".failed"));
  EXPECT_FALSE(fs::exists(folder + ".partial"));
  EXPECT_FALSE(fs::exists(folder));
}

// A long run (many small load steps), stopped by SIGTERM once its first step is written.
class Interrupted : public ::testing::TestWithParam<int> {};

TEST_P(Interrupted, BySigtermKeepsTheStepsSoFarAndExits143) {
  const int ranks = GetParam();
  TempFolder tmp;
  const std::string folder = (tmp.path() / "beam").string();
  const std::string err = (tmp.path() / "err").string();
  std::string command = cantilever(folder, "--set time.steps=20000") + " 2> " + err;
  if (ranks > 1) command = std::string(HYDROSOFT_MPIEXEC) + " -np 2 " + command;
  const pid_t pid = start(command);
  // The first step's history row is written after its .h5 step: the run is stepping.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (!fs::exists(folder + ".partial/history.csv") &&
         std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_TRUE(fs::exists(folder + ".partial/history.csv")) << text_of(err);
  // On 2 ranks only the last rank gets the signal, as from a scheduler that signals one
  // process: the ranks agree at the next step boundary all the same.
  pid_t target = pid;
  if (ranks > 1) {
    std::stringstream children(
        text_of("/proc/" + std::to_string(pid) + "/task/" + std::to_string(pid) + "/children"));
    for (pid_t child; children >> child;) target = child;
    ASSERT_NE(target, pid) << "no rank process found under mpiexec";
  }
  ASSERT_EQ(kill(target, SIGTERM), 0);
  EXPECT_EQ(wait_for(pid), 143) << text_of(err);

  const std::string failed = folder + ".failed";
  ASSERT_TRUE(fs::is_directory(failed)) << text_of(err);
  EXPECT_FALSE(fs::exists(folder));
  EXPECT_FALSE(fs::exists(folder + ".partial"));
  const auto summary = json_of(failed + "/summary.json");
  EXPECT_EQ(summary["status"], "failed");
  EXPECT_EQ(summary["reason"], "interrupted by SIGTERM");
  const int steps = summary["outputs"].get<int>();
  EXPECT_GE(steps, 1);
  EXPECT_LT(steps, 20000);  // stopped, not finished
  EXPECT_EQ(h5_steps(failed + "/cantilever_gravity.h5"), steps);
  EXPECT_EQ(xmf_grids(failed + "/cantilever_gravity.xmf"), steps);
  const Csv csv = csv_of(failed + "/history.csv");
  ASSERT_EQ(csv.rows.size(), static_cast<size_t>(steps));
  EXPECT_EQ(summary["last_converged"]["step"], steps - 1);
  // The last step written is the last one converged: load factor k / 20000 at step k - 1.
  EXPECT_DOUBLE_EQ(summary["last_converged"]["load_factor"].get<double>(), steps / 20000.0);
  EXPECT_DOUBLE_EQ(csv.rows.back()[csv.column("load_factor")], steps / 20000.0);
  EXPECT_NE(text_of(err).find("hydrosoft: interrupted by SIGTERM; the " + std::to_string(steps) +
                              " converged output steps are in " + failed),
            std::string::npos)
      << text_of(err);
}

INSTANTIATE_TEST_SUITE_P(Ranks, Interrupted, ::testing::Values(1, 2));

// The exit status of `pid` if it ends within `seconds`; else it is killed (SIGKILL) and -2.
int wait_at_most(pid_t pid, double seconds) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  int status = 0;
  while (std::chrono::steady_clock::now() < deadline) {
    const pid_t done = waitpid(pid, &status, WNOHANG);
    if (done == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  kill(pid, SIGKILL);
  waitpid(pid, &status, 0);
  return -2;
}

// The Gent sphere with nu = 0 converges 7 load steps, then cuts step 8 back for minutes (its
// sub-steps converge and the doubled increment after each fails). SIGTERM during those
// cutbacks: before, the signal was looked at only when a step ended, so the run went on (400 s
// and more, until SIGKILL, leaving only .partial); now the cutback loop asks before every
// solve, and the run stops within one, keeping its 7 steps.
class InterruptedCutback : public ::testing::TestWithParam<int> {};

TEST_P(InterruptedCutback, SigtermStopsAStepThatCutsBackWithinOneSolve) {
  const int ranks = GetParam();
  TempFolder tmp;
  const std::string folder = (tmp.path() / "sphere").string();
  const std::string err = (tmp.path() / "err").string();
  std::string command = std::string(HYDROSOFT_EXE) + " " + kSource +
                        "/input/gent_sphere.yaml -q --set materials[0].nu=0 "
                        "--set mesh.parameters.h=0.5 --set output.folder=" +
                        folder + " 2> " + err;
  if (ranks > 1) command = std::string(HYDROSOFT_MPIEXEC) + " -np 2 " + command;
  const pid_t pid = start(command);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  auto rows = [&] {
    std::ifstream in(folder + ".partial/history.csv");
    int n = 0;
    for (std::string line; std::getline(in, line);) ++n;
    return n - 1;
  };
  while (rows() < 7 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_EQ(rows(), 7) << text_of(err);
  std::this_thread::sleep_for(std::chrono::seconds(1));  // into step 8's cutbacks
  pid_t target = pid;
  if (ranks > 1) {
    std::stringstream children(
        text_of("/proc/" + std::to_string(pid) + "/task/" + std::to_string(pid) + "/children"));
    for (pid_t child; children >> child;) target = child;
    ASSERT_NE(target, pid) << "no rank process found under mpiexec";
  }
  const auto signalled = std::chrono::steady_clock::now();
  ASSERT_EQ(kill(target, SIGTERM), 0);
  EXPECT_EQ(wait_at_most(pid, 60), 143) << text_of(err);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - signalled).count();
  std::cout << "stopped " << seconds << " s after SIGTERM" << std::endl;
  const auto summary = json_of(folder + ".failed/summary.json");
  EXPECT_EQ(summary["reason"], "interrupted by SIGTERM");
  EXPECT_EQ(summary["outputs"], 7);
  EXPECT_GT(summary["cutbacks"].get<int>(), 0);
  EXPECT_DOUBLE_EQ(summary["last_converged"]["load_factor"].get<double>(), 0.7);
  EXPECT_EQ(h5_steps(folder + ".failed/gent_sphere.h5"), 7);
}

INSTANTIATE_TEST_SUITE_P(Ranks, InterruptedCutback, ::testing::Values(1, 2));

TEST(InterruptedInteractive, ASignalWhileWaitingForATargetStopsTheReading) {
  TempFolder tmp;
  const std::string folder = (tmp.path() / "finger").string();
  const std::string fifo = (tmp.path() / "targets").string(), out = (tmp.path() / "out").string(),
                    err = (tmp.path() / "err").string();
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  const pid_t pid = start(std::string(HYDROSOFT_EXE) + " " + kSource +
                          "/input/finger_hydraulic.yaml -q " + hs_test::compressible_finger_args() +
                          "--set mesh.parameters.h=0.006 "
                          "--set control.steps_per_target=1 --set output.folder=" +
                          folder + " --targets - < " + fifo + " > " + out + " 2> " + err);
  const int targets = open(fifo.c_str(), O_WRONLY);  // held open: the input never ends
  ASSERT_GE(targets, 0);
  const std::string line = "0.09 0 -0.012\n";
  ASSERT_EQ(write(targets, line.data(), line.size()), static_cast<ssize_t>(line.size()));
  // Its answer is out: the run is waiting for the next line.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (text_of(out).find("answer") == std::string::npos &&
         std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_NE(text_of(out).find("answer"), std::string::npos) << text_of(err);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  ASSERT_EQ(kill(pid, SIGTERM), 0);
  EXPECT_EQ(wait_for(pid), 143) << text_of(err);
  close(targets);
  const auto summary = json_of(folder + ".failed/summary.json");
  EXPECT_EQ(summary["reason"], "interrupted by SIGTERM");
  EXPECT_EQ(summary["outputs"], 5);  // the 4 steps of the state, the one target
  EXPECT_EQ(summary["last_converged"]["step"], 4);
  EXPECT_EQ(csv_of(folder + ".failed/history.csv").rows.size(), 5u);
}

TEST(History, EveryOutputStepHasARowEqualToTheSummaryAndTheH5) {
  TempFolder tmp;
  const std::string folder = (tmp.path() / "finger").string();
  const std::string err = (tmp.path() / "err").string();
  // The small finger, two deck targets: 4 state steps and 2 control steps.
  const std::string command = std::string(HYDROSOFT_EXE) + " " + kSource +
                              "/input/finger_hydraulic.yaml -q " +
                              hs_test::compressible_finger_args() +
                              "--set mesh.parameters.h=0.006 "
                              "--set control.steps_per_target=2 "
                              "--set 'control.targets=[{tip: [0.09, 0, -0.012]}, "
                              "{tip: [0.09, 0, -0.008]}]' --set output.folder=" +
                              folder + " > /dev/null 2> " + err;
  ASSERT_EQ(run(command), 0) << text_of(err);
  const auto summary = json_of(folder + "/summary.json");
  EXPECT_EQ(summary["status"], "ok");
  const Csv csv = csv_of(folder + "/history.csv");
  const std::vector<std::string> expected = {"step",
                                             "state",
                                             "newton_iterations",
                                             "cavity_cavity_pressure_Pa",
                                             "cavity_cavity_volume_m3",
                                             "cavity_cavity_added_volume_m3",
                                             "cavity_cavity_fluid_weight_N",
                                             "effector_tip_x_m",
                                             "effector_tip_y_m",
                                             "effector_tip_z_m",
                                             "actuator_cavity_Pa",
                                             "reaction_base_x_N",
                                             "reaction_base_y_N",
                                             "reaction_base_z_N"};
  EXPECT_EQ(csv.header, expected);
  ASSERT_EQ(csv.rows.size(), summary["outputs"].get<size_t>());
  ASSERT_EQ(csv.rows.size(), 6u);
  for (size_t k = 0; k < csv.rows.size(); ++k) EXPECT_EQ(csv.rows[k][0], k);
  const auto& last = csv.rows.back();
  const auto& cavity = summary["end_of_run"]["cavities"][0];
  EXPECT_EQ(last[csv.column("cavity_cavity_pressure_Pa")], cavity["pressure"].get<double>());
  EXPECT_EQ(last[csv.column("cavity_cavity_volume_m3")], cavity["volume"].get<double>());
  EXPECT_NEAR(last[csv.column("cavity_cavity_added_volume_m3")] * 1e6,
              cavity["added_volume_ml"].get<double>(), 1e-12);
  EXPECT_EQ(last[csv.column("cavity_cavity_fluid_weight_N")],
            cavity["fluid_weight_total"].get<double>());
  EXPECT_GT(last[csv.column("cavity_cavity_fluid_weight_N")], 0);
  // The clamp's reaction at the last step is the run's.
  for (int d = 0; d < 3; ++d)
    EXPECT_EQ(last[csv.column(std::string("reaction_base_") + "xyz"[d] + "_N")],
              summary["reactions_N"]["base"][d].get<double>());
  // Each target set's row: its effector where summary.json says it was reached, its actuation.
  for (size_t t = 0; t < 2; ++t) {
    const auto& target = summary["targets"][t];
    const auto& row = csv.rows[target["step"].get<size_t>()];
    EXPECT_EQ(row[csv.column("state")], 2.0 + t);  // after the one state
    EXPECT_EQ(row[csv.column("effector_tip_z_m")], target["reached"][2].get<double>());
    EXPECT_EQ(row[csv.column("actuator_cavity_Pa")], target["actuation"][0].get<double>());
  }
  // The first state ramps the load: the end of the state is row 3, at state 1.
  EXPECT_EQ(csv.rows[3][csv.column("state")], 1.0);
  EXPECT_EQ(csv.rows[3][csv.column("cavity_cavity_volume_m3")],
            summary["states"][0]["cavities"][0]["volume"].get<double>());
  // Newton iterations: the rows add up to the stepping's total and the control steps'.
  double newton = 0;
  for (const auto& row : csv.rows) newton += row[csv.column("newton_iterations")];
  EXPECT_GE(newton, summary["newton_iterations"].get<double>());
  double state_newton = 0;
  for (size_t k = 0; k < 4; ++k) state_newton += csv.rows[k][csv.column("newton_iterations")];
  EXPECT_EQ(state_newton, summary["newton_iterations"].get<double>());
  // The same values in the .h5, one dataset per column.
  const std::string h5 = folder + "/finger_hydraulic.h5";
  for (size_t c = 0; c < csv.header.size(); ++c) {
    const auto values = h5_column(h5, "/history/" + csv.header[c]);
    ASSERT_EQ(values.size(), csv.rows.size()) << csv.header[c];
    for (size_t k = 0; k < values.size(); ++k) EXPECT_EQ(values[k], csv.rows[k][c]);
  }
}

TEST(History, AStaticRunNamesItsLoadFactor) {
  TempFolder tmp;
  const std::string folder = (tmp.path() / "beam").string();
  ASSERT_EQ(run(cantilever(folder, "--set time.steps=4 --set output.every=2")), 0);
  const Csv csv = csv_of(folder + "/history.csv");
  EXPECT_EQ(csv.header, (std::vector<std::string>{"step", "load_factor", "newton_iterations",
                                                  "reaction_clamped_x_N", "reaction_clamped_y_N",
                                                  "reaction_clamped_z_N"}));
  ASSERT_EQ(csv.rows.size(), 2u);  // every 2nd of 4 steps
  EXPECT_EQ(csv.rows[0][1], 0.5);
  EXPECT_EQ(csv.rows[1][1], 1.0);
  // The clamp carries the weight at the row's load factor: rho g L h^2 = 24.525 N in full.
  EXPECT_NEAR(csv.rows[0][csv.column("reaction_clamped_z_N")], 0.5 * 24.525, 1e-8);
  EXPECT_NEAR(csv.rows[1][csv.column("reaction_clamped_z_N")], 24.525, 1e-8);
  EXPECT_EQ(csv.rows[1][csv.column("reaction_clamped_z_N")],
            json_of(folder + "/summary.json")["reactions_N"]["clamped"][2].get<double>());
  EXPECT_EQ(json_of(folder + "/summary.json")["outputs"], 2);
  EXPECT_EQ(h5_column(folder + "/cantilever_gravity.h5", "/history/load_factor"),
            (std::vector<double>{0.5, 1.0}));
}

// ---- A disk that fills ----

// A small disk for one test: a tmpfs of `kb` KB when this process may mount one (root with
// CAP_SYS_ADMIN); otherwise a file size limit of `limit_kb` KB on every rank (ulimit -f,
// SIGXFSZ ignored), which hydrosoft meets the same way: its room for a write is refused
// ("File too large" instead of "No space left on device").
class SmallDisk {
 public:
  SmallDisk(int kb, int limit_kb) : kb_(limit_kb) {
    fs::create_directories(path());
    const std::string size = "size=" + std::to_string(kb) + "k";
    mounted_ = mount("tmpfs", path().c_str(), "tmpfs", 0, size.c_str()) == 0;
  }
  ~SmallDisk() {
    if (mounted_) umount2(path().c_str(), MNT_DETACH);
  }
  SmallDisk(const SmallDisk&) = delete;
  SmallDisk& operator=(const SmallDisk&) = delete;

  std::string path() const { return (tmp_.path() / "disk").string(); }
  bool mounted() const { return mounted_; }
  const char* reason() const { return mounted_ ? "No space left on device" : "File too large"; }
  // `command` (a hydrosoft command line) on `ranks` ranks, with this disk's limit.
  std::string run_on(int ranks, const std::string& command) const {
    if (mounted_)
      return ranks == 1
                 ? command
                 : std::string(HYDROSOFT_MPIEXEC) + " -np " + std::to_string(ranks) + " " + command;
    // Each rank under the limit, not mpiexec (whose own files are larger); TCP between the
    // ranks, whose shared-memory transport would meet the limit too. POSIX sh counts the
    // limit in blocks of 512 bytes.
    return std::string(HYDROSOFT_MPIEXEC) + " --mca btl self,tcp -np " + std::to_string(ranks) +
           " sh -c \"ulimit -f " + std::to_string(2 * kb_) + "; trap '' XFSZ; exec " + command +
           "\"";
  }

 private:
  TempFolder tmp_;
  int kb_ = 0;
  bool mounted_ = false;
};

// Runs `command` in its own process group; its exit status, or -2 when it is still going
// after `seconds` (then the whole group is killed: a run that hangs fails the test).
int run_with_time_limit(const std::string& command, int seconds) {
  const pid_t pid = fork();
  if (pid == 0) {
    setpgid(0, 0);
    execl("/bin/sh", "sh", "-c", ("exec " + command).c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(seconds);
  int status = 0;
  while (waitpid(pid, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() > deadline) {
      kill(-pid, SIGKILL);
      waitpid(pid, &status, 0);
      return -2;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// The lines of a text that start with `prefix`.
std::vector<std::string> lines_starting(const std::string& text, const std::string& prefix) {
  std::vector<std::string> lines;
  std::stringstream s(text);
  for (std::string line; std::getline(s, line);)
    if (line.rfind(prefix, 0) == 0) lines.push_back(line);
  return lines;
}

class DiskFull : public ::testing::TestWithParam<int> {};

// The cantilever's 100 output steps of 33 KB each do not fit in 1 MB (or a file of 300 KB):
// the step that finds no room is refused before HDF5 writes it. Before: on 2 ranks the run
// hung with nothing printed; on 1 rank it ended with exit status 4 and every step lost.
TEST_P(DiskFull, AtAStepEveryRankEndsWithOneLineAndTheStepsBeforeAreKept) {
  const int ranks = GetParam();
  const SmallDisk disk(1024, 300);
  const std::string folder = disk.path() + "/beam", err = disk.path() + "/../err";
  const int status = run_with_time_limit(
      disk.run_on(ranks, cantilever(folder, "--set time.steps=100")) + " > /dev/null 2> " + err,
      120);
  ASSERT_NE(status, -2) << "the run hung\n" << text_of(err);
  EXPECT_EQ(status, 3) << text_of(err);
  const std::string log = text_of(err);
  const auto errors = lines_starting(log, "hydrosoft: error:");
  ASSERT_EQ(errors.size(), 1u) << log;
  // The step's .h5 part finds no room, or (on the tmpfs, where the .xmf is rewritten beside
  // the old one) its .xmf.
  const std::regex expected(".*: output step [0-9]+ \\(time [0-9.e-]+\\) not written: " + folder +
                            "\\.partial/cantilever_gravity\\.(h5: no room for [0-9]+ KB more|xmf: "
                            "cannot write the file): " +
                            disk.reason());
  EXPECT_TRUE(std::regex_match(errors[0], expected)) << errors[0];
  EXPECT_EQ(log.find("HDF5-DIAG"), std::string::npos) << log;
  const std::string failed = folder + ".failed";
  ASSERT_TRUE(fs::is_directory(failed)) << log;
  EXPECT_FALSE(fs::exists(folder + ".partial"));
  EXPECT_FALSE(fs::exists(folder + ".lock"));
  const auto summary = json_of(failed + "/summary.json");
  EXPECT_EQ(summary["status"], "failed");
  const int steps = summary["outputs"].get<int>();
  EXPECT_GE(steps, 2);
  EXPECT_LT(steps, 100);
  EXPECT_EQ(summary["reason"], errors[0].substr(errors[0].find(": output step ") + 2));
  EXPECT_NE(log.find("\n  the " + std::to_string(steps) + " converged output steps are in " +
                     failed + "/"),
            std::string::npos)
      << log;
  EXPECT_EQ(xmf_grids(failed + "/cantilever_gravity.xmf"), steps);
  EXPECT_EQ(csv_of(failed + "/history.csv").rows.size(), static_cast<size_t>(steps));
  // The .h5 opens; a step refused at its .xmf left its group there, named by nothing.
  const int groups = h5_steps(failed + "/cantilever_gravity.h5");
  EXPECT_EQ(groups, errors[0].find(".xmf: ") == std::string::npos ? steps : steps + 1);
}

// A checkpoint that finds no room, with no output step before it: the run ends with exit
// status 3 and the previous checkpoint kept, and a restart from it (on a disk with room)
// finishes the run. Before: 1,800 lines of HDF5's error stack, then SIGSEGV in MPI_Finalize.
TEST_P(DiskFull, AtACheckpointTheRunEndsAndThePreviousCheckpointIsKept) {
  const int ranks = GetParam();
  const SmallDisk disk(160, 0);
  if (!disk.mounted()) GTEST_SKIP() << "no tmpfs can be mounted here (needs CAP_SYS_ADMIN)";
  const std::string folder = disk.path() + "/beam", err = disk.path() + "/../err";
  const std::string every = "--set time.steps=100 --set output.every=1000 ";
  const int status = run_with_time_limit(
      disk.run_on(ranks, cantilever(folder, every + "--set 'output.checkpoint={every: 1}'")) +
          " > /dev/null 2> " + err,
      120);
  ASSERT_NE(status, -2) << "the run hung\n" << text_of(err);
  EXPECT_EQ(status, 3) << text_of(err);
  const auto errors = lines_starting(text_of(err), "hydrosoft: error:");
  ASSERT_EQ(errors.size(), 1u) << text_of(err);
  EXPECT_NE(errors[0].find(": checkpoint not written: " + folder +
                           ".partial/checkpoint.h5.tmp: no room for "),
            std::string::npos)
      << errors[0];
  EXPECT_NE(errors[0].find("No space left on device"), std::string::npos) << errors[0];
  const std::string failed = folder + ".failed";
  ASSERT_TRUE(fs::exists(failed + "/checkpoint.h5")) << text_of(err);
  EXPECT_FALSE(fs::exists(failed + "/checkpoint.h5.tmp"));
  EXPECT_EQ(json_of(failed + "/summary.json")["status"], "failed");
  // Continued elsewhere from the kept checkpoint, to the end.
  TempFolder roomy;
  const std::string rest = (roomy.path() / "rest").string();
  EXPECT_EQ(run(cantilever(rest, every + "--restart " + failed) + " > /dev/null 2>> " + err), 0)
      << text_of(err);
  EXPECT_EQ(json_of(rest + "/summary.json")["status"], "ok");
}

INSTANTIATE_TEST_SUITE_P(Ranks, DiskFull, ::testing::Values(1, 2));

}  // namespace test_run_outcomes
}  // namespace
