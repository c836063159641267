// The hydrosoft executable as a client or a user runs it: in the interactive mode
// (`--targets -`) standard output carries only the JSON lines, one per input line, whatever
// else the run prints (its configuration, its summary, a PETSc-level monitor), on 1 and 2
// ranks; a client that closes its pipes mid-step ends the session with its steps kept; a
// second run on the output folder of a run in progress fails at once while the first one
// finishes with consistent results; an option with a misspelt solver-object prefix stops the
// run before any work; and a mesh that hides a shell command where the checks
// before gmsh once did not look runs no command, however the run is started.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "../deck/temp_folder.hpp"
#include "../pinned_decks.hpp"
#include "child_process.hpp"
#include "text_file.hpp"

namespace {

namespace fs = std::filesystem;
using hs::testing::TempFolder;

const std::string kFinger = std::string(HYDROSOFT_SOURCE_DIR) + "/input/finger_hydraulic.yaml";

// The small finger in its compressible material (../pinned_decks.hpp), writing into `folder`.
std::string finger_command(const std::string& folder) {
  return std::string(HYDROSOFT_EXE) + " " + kFinger + " " + hs_test::compressible_finger_args() +
         "--set mesh.parameters.h=0.006 --set control.steps_per_target=1 --set output.folder=" +
         folder;
}

using hs::testing::start;
using hs::testing::wait_for;

std::vector<std::string> lines_of(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

using hs::testing::text_of;

class InteractiveOutput : public ::testing::TestWithParam<int> {};

TEST_P(InteractiveOutput, StandardOutputHoldsOnlyTheJsonLines) {
  const int ranks = GetParam();
  TempFolder tmp;
  const std::string input =
      tmp.write("in.txt", "0.09 0 -0.012\n1 2\n\n0.09 0 nan\n0.09 0 -0.008\n");
  const std::string out = (tmp.path() / "out.txt").string(),
                    err = (tmp.path() / "err.txt").string();
  std::string command = finger_command((tmp.path() / "run").string()) +
                        " --targets - -hs_newton_monitor < " + input + " > " + out + " 2> " + err;
  if (ranks > 1) command = std::string(HYDROSOFT_MPIEXEC) + " -np 2 " + command;
  ASSERT_EQ(wait_for(start(command)), 0) << text_of(err);
  // -hs_newton_monitor, the bordered Newton's monitor's name before -hs_bordered_monitor,
  // still prints its lines (on standard error).
  EXPECT_NE(text_of(err).find("|R|"), std::string::npos) << text_of(err);
  const auto lines = lines_of(out);
  ASSERT_EQ(lines.size(), 5u) << text_of(out);
  for (size_t k = 0; k < lines.size(); ++k) {
    const auto j = nlohmann::json::parse(lines[k]);  // every line is one JSON object
    EXPECT_EQ(j["line"], k + 1);
    EXPECT_EQ(j.contains("answer"), k == 0 || k == 4) << lines[k];
    EXPECT_EQ(j.contains("error"), k != 0 && k != 4) << lines[k];
  }
  // The rest went to standard error: configuration, the monitor's lines, the summary.
  const std::string messages = text_of(err);
  EXPECT_NE(messages.find("# hydrosoft: resolved configuration"), std::string::npos);
  EXPECT_NE(messages.find("|R|"), std::string::npos);
  EXPECT_NE(messages.find("# hydrosoft: done"), std::string::npos);
  EXPECT_NE(messages.find("line 2 refused"), std::string::npos);
}

INSTANTIATE_TEST_SUITE_P(Ranks, InteractiveOutput, ::testing::Values(1, 2));

// A client that reads one answer, sends a second line and closes both its pipes while that
// line is being stepped. Before, the answer's write raised SIGPIPE: a PETSc dump, exit 59,
// only `.partial` left. Now the write's EPIPE ends the session: exit 0 and the folder holds
// both answered steps. Under mpiexec the ranks write to mpiexec, which holds the pipe and
// drops what it cannot pass on: the session ends at the end of its input, the same results.
class ClientGoesAway : public ::testing::TestWithParam<int> {};

TEST_P(ClientGoesAway, ClosingBothPipesMidStepKeepsTheAnsweredSteps) {
  const int ranks = GetParam();
  TempFolder tmp;
  const std::string folder = (tmp.path() / "run").string();
  const std::string in_fifo = (tmp.path() / "in").string(),
                    out_fifo = (tmp.path() / "out").string(), err = (tmp.path() / "err").string();
  ASSERT_EQ(mkfifo(in_fifo.c_str(), 0600), 0);
  ASSERT_EQ(mkfifo(out_fifo.c_str(), 0600), 0);
  // 4 control steps a target: the second line's step outlasts the client's closing.
  std::string command = finger_command(folder) + " -q --set control.steps_per_target=4 " +
                        "--targets - < " + in_fifo + " > " + out_fifo + " 2> " + err;
  if (ranks > 1) command = std::string(HYDROSOFT_MPIEXEC) + " -np 2 " + command;
  const pid_t pid = start(command);
  const int to_run = open(in_fifo.c_str(), O_WRONLY);
  const int from_run = open(out_fifo.c_str(), O_RDONLY);
  ASSERT_GE(to_run, 0);
  ASSERT_GE(from_run, 0);
  const std::string first = "0.09 0 -0.012\n", second = "0.09 0 -0.008\n";
  ASSERT_EQ(write(to_run, first.data(), first.size()), static_cast<ssize_t>(first.size()));
  std::string answer;
  for (char c = 0; c != '\n' && read(from_run, &c, 1) == 1;) answer += c;
  ASSERT_NE(answer.find("\"answer\""), std::string::npos) << answer << text_of(err);
  ASSERT_EQ(write(to_run, second.data(), second.size()), static_cast<ssize_t>(second.size()));
  close(from_run);
  close(to_run);
  EXPECT_EQ(wait_for(pid), 0) << text_of(err);

  const auto summary = nlohmann::json::parse(text_of(folder + "/summary.json"));
  EXPECT_EQ(summary["status"], "ok");
  EXPECT_EQ(summary["targets"].size(), 2u);
  EXPECT_EQ(summary["outputs"], 4 + 2);
  EXPECT_EQ(summary["input"]["lines"], 2);
  if (ranks == 1) {
    EXPECT_EQ(summary["input"]["end"], "standard output closed");
    EXPECT_EQ(summary["input"]["undelivered"], 1);
    EXPECT_NE(text_of(err).find("hydrosoft: standard output is closed (the client is gone)"),
              std::string::npos)
        << text_of(err);
  }
  EXPECT_EQ(text_of(err).find("PETSC ERROR"), std::string::npos) << text_of(err);
  EXPECT_FALSE(fs::exists(folder + ".partial"));
  EXPECT_FALSE(fs::exists(folder + ".failed"));
}

INSTANTIATE_TEST_SUITE_P(Ranks, ClientGoesAway, ::testing::Values(1, 2));

TEST(SharedOutputFolder, ASecondRunFailsAtOnceAndTheFirstFinishes) {
  TempFolder tmp;
  const std::string folder = (tmp.path() / "run").string();
  const std::string fifo = (tmp.path() / "targets").string();
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  // The first run waits for its targets (holding the folder) until the test sends them.
  const pid_t first =
      start(finger_command(folder) + " --targets - < " + fifo + " > " +
            (tmp.path() / "first.out").string() + " 2> " + (tmp.path() / "first.err").string());
  const int targets = open(fifo.c_str(), O_WRONLY);
  ASSERT_GE(targets, 0);
  // Its staging folder appears once it holds the folder (and, unlocked, would be deleted).
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (!fs::exists(folder + ".partial") && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_TRUE(fs::exists(folder + ".partial"));

  const std::string second_err = (tmp.path() / "second.err").string();
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(wait_for(start(finger_command(folder) + " > /dev/null 2> " + second_err)), 2);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const std::string message = text_of(second_err);
  EXPECT_NE(message.find("hydrosoft: error: output folder '" + folder +
                         "': another run is writing it (process"),
            std::string::npos)
      << message;
  std::cout << "the second run stopped after " << seconds << " s" << std::endl;

  const std::string line = "0.09 0 -0.012\n";
  ASSERT_EQ(write(targets, line.data(), line.size()), static_cast<ssize_t>(line.size()));
  close(targets);
  ASSERT_EQ(wait_for(first), 0) << text_of((tmp.path() / "first.err").string());
  // The first run's results, whole: every output step of the .xmf, the summary's count.
  const auto summary = nlohmann::json::parse(text_of(folder + "/summary.json"));
  EXPECT_EQ(summary["targets"].size(), 1u);
  const std::string xmf = text_of(folder + "/finger_hydraulic.xmf");
  int grids = 0;
  for (size_t at = xmf.find("GridType=\"Uniform\""); at != std::string::npos;
       at = xmf.find("GridType=\"Uniform\"", at + 1))
    ++grids;
  EXPECT_EQ(grids, summary["outputs"].get<int>());
  EXPECT_FALSE(fs::exists(folder + ".partial"));
  EXPECT_FALSE(fs::exists(folder + ".lock"));
}

// An option with a misspelt object prefix was read by nothing and the run went on without a
// word. Now the run, and --check, stop before any work, naming the option and its source.
TEST(SolverOptions, AMisspeltPrefixStopsTheRunNamingTheOption) {
  const TempFolder dir;
  const std::string deck = std::string(HYDROSOFT_SOURCE_DIR) + "/input/hydrostatic_patch.yaml";
  const std::string out = (dir.path() / "out").string(), err = (dir.path() / "err.txt").string();
  const std::string run = std::string(HYDROSOFT_EXE) + " " + deck + " --set output.folder=" + out;
  const struct {
    std::string command, message;
  } cases[] = {
      {run + " -hs_bordred_ksp_type preonly",
       "hydrosoft: error: command line: -hs_bordred_ksp_type: unknown hydrosoft option prefix "
       "(did you mean -hs_bordered_ksp_type?"},
      {run + " --set solver.petsc_options.hs_nwton_ksp_type=cg",
       "hydrosoft: error: " + deck +
           ": solver.petsc_options.hs_nwton_ksp_type: unknown hydrosoft option prefix (did you "
           "mean hs_newton_ksp_type?"},
      {std::string(HYDROSOFT_EXE) + " --check " + deck + " -hs_mas_ksp_rtol 1e-9",
       "hydrosoft: error: command line: -hs_mas_ksp_rtol: unknown hydrosoft option prefix (did "
       "you mean -hs_mass_ksp_rtol?"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.command);
    EXPECT_EQ(hs::testing::run(c.command + " > /dev/null 2> " + err), 2);
    const std::string message = text_of(err);
    EXPECT_NE(message.find(c.message), std::string::npos) << message;
    EXPECT_FALSE(fs::exists(out));
  }
}

// hs_volume_monitor prints a line per Newton solve at the multipliers of a body at nu = 0.5:
// the summary's solves and raises. The deck's option was accepted and then read by nothing.
TEST(SolverOptions, TheVolumeMonitorIsReadFromTheDeckAndFromTheCommandLine) {
  const TempFolder dir;
  const std::string deck = std::string(HYDROSOFT_SOURCE_DIR) + "/input/stretched_block.yaml";
  const std::string out = (dir.path() / "out").string(), log = (dir.path() / "log.txt").string();
  const std::string run =
      std::string(HYDROSOFT_EXE) + " " + deck + " -q --set output.folder=" + out + " --set ";
  for (const std::string& option : {"solver.petsc_options.hs_volume_monitor=true",
                                    "output.progress=false -hs_volume_monitor"}) {
    SCOPED_TRACE(option);
    fs::remove_all(out);
    ASSERT_EQ(hs::testing::run(run + option + " > " + log + " 2>&1"), 0) << text_of(log);
    const std::string text = text_of(log);
    int lines = 0;
    for (size_t at = text.find("  volume multipliers: "); at != std::string::npos;
         at = text.find("  volume multipliers: ", at + 1))
      ++lines;
    const auto kept = nlohmann::json::parse(text_of(out + "/summary.json"))["incompressibility"];
    EXPECT_GT(kept["multiplier_raises"].get<int>(), 0);
    EXPECT_EQ(lines, kept["solves"].get<int>() + kept["multiplier_raises"].get<int>()) << text;
  }
}

// A .geo whose shell command hides in a file it merges (any name: gmsh reads an unknown one as
// a script) or in the options file beside it: the command ran under a normal run, `--check`,
// `hydrosoft mesh` and 2 ranks, with the deck's mesh parameters.
TEST(UntrustedMesh, AHiddenShellCommandRunsInNoWayOfStartingTheRun) {
  const TempFolder dir;
  const std::string marker = (dir.path() / "ran").string();
  const std::string block = text_of(std::string(HYDROSOFT_SOURCE_DIR) + "/meshes/block.geo");
  const std::string deck =
      text_of(std::string(HYDROSOFT_SOURCE_DIR) + "/input/hydrostatic_patch.yaml");
  const std::string payload = "SystemCall \"touch " + marker + "\";\n";
  for (const bool beside : {false, true}) {
    SCOPED_TRACE(beside ? "in block.geo.opt" : "in a merged payload.txt");
    const TempFolder case_dir;
    if (beside)
      case_dir.write("block.geo.opt", payload);
    else
      case_dir.write("payload.txt", payload);
    case_dir.write("block.geo", (beside ? "" : "Merge \"payload.txt\";\n") + block);
    const std::string yaml = case_dir.write("patch.yaml", deck);
    const std::string hidden =
        (case_dir.path() / (beside ? "block.geo.opt" : "payload.txt")).string();
    const std::string set =
        " --set mesh.file=block.geo --set output.folder=" + (case_dir.path() / "out").string() +
        " > /dev/null 2> " + (case_dir.path() / "err.txt").string();
    std::vector<std::string> commands = {std::string(HYDROSOFT_EXE) + " " + yaml + set};
    if (!beside)  // the other ways reach the same check
      commands.insert(commands.end(), {std::string(HYDROSOFT_EXE) + " --check " + yaml + set,
                                       std::string(HYDROSOFT_EXE) + " mesh " + yaml + " " +
                                           (case_dir.path() / "m.h5").string() + set,
                                       std::string(HYDROSOFT_MPIEXEC) + " -np 2 " + HYDROSOFT_EXE +
                                           " " + yaml + set});
    for (const std::string& command : commands) {
      SCOPED_TRACE(command);
      EXPECT_EQ(hs::testing::run(command), 2);
      const std::string err = text_of((case_dir.path() / "err.txt").string());
      EXPECT_NE(err.find(hidden + ": SystemCall: runs a shell command"), std::string::npos) << err;
      EXPECT_FALSE(fs::exists(marker));
      EXPECT_FALSE(fs::exists(case_dir.path() / "m.h5"));
      EXPECT_FALSE(fs::exists(case_dir.path() / "out"));
    }
  }
}

// SIGTERM (a cluster's time limit) waited for gmsh to finish meshing, however long that took.
TEST(UntrustedMesh, SigtermStopsTheRunWhileGmshMeshes) {
  const TempFolder dir;
  const std::string block = text_of(std::string(HYDROSOFT_SOURCE_DIR) + "/meshes/block.geo");
  dir.write("block.geo", "For i In {1:2e9}\nEndFor\n" + block);  // minutes of parsing
  const std::string yaml = dir.write(
      "patch.yaml", text_of(std::string(HYDROSOFT_SOURCE_DIR) + "/input/hydrostatic_patch.yaml"));
  const std::string err = (dir.path() / "err.txt").string();
  const pid_t run = hs::testing::start(std::string(HYDROSOFT_EXE) + " " + yaml +
                                       " --set mesh.file=block.geo --set output.folder=" +
                                       (dir.path() / "out").string() + " > /dev/null 2> " + err);
  // gmsh's process: a fork of the run that is still the run's program half a second later (the
  // singleton's orted is a fork of the run too, for the moment before its exec).
  const auto fork_of = [](pid_t run, pid_t pid) {
    std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
    std::string text((std::istreambuf_iterator<char>(stat)), {});
    const size_t close = text.rfind(')');
    if (close == std::string::npos || text.find("(hydrosoft)") == std::string::npos) return false;
    std::istringstream fields(text.substr(close + 2));
    std::string state;
    pid_t parent = 0;
    return fields >> state >> parent && parent == run;
  };
  pid_t gmsh = 0;
  for (int i = 0; i < 600 && gmsh == 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    for (const auto& entry : fs::directory_iterator("/proc")) {
      const std::string name = entry.path().filename();
      if (name.find_first_not_of("0123456789") != std::string::npos) continue;  // not a process
      if (fork_of(run, std::stoi(name))) gmsh = std::stoi(name);
    }
    if (gmsh == 0) continue;
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    if (!fork_of(run, gmsh)) gmsh = 0;
  }
  ASSERT_GT(gmsh, 0) << text_of(err);
  const auto start = std::chrono::steady_clock::now();
  kill(run, SIGTERM);
  EXPECT_EQ(wait_for(run), 143) << text_of(err);
  EXPECT_NE(kill(gmsh, 0), 0) << "gmsh's process outlived the run";
  // Far below the minutes of parsing, with room for a sanitized build's exit (6 s).
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 30);
  EXPECT_NE(text_of(err).find("interrupted by SIGTERM"), std::string::npos) << text_of(err);
  EXPECT_FALSE(fs::exists(dir.path() / "out"));
}

}  // namespace
