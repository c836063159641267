// The interactive mode (`hydrosoft DECK --targets -`, docs/control.md) inside the process, on
// 1 and 2 ranks: every line gets exactly one JSON line; a bad one (wrong count of words, not
// a number, NaN or inf, a target too far to be answered, an empty line, an unknown effector,
// a megabyte of garbage) gets an error naming its line and changes nothing, and the loop goes
// on to the end of the input, or until its answers can no longer be written; the run's
// results are kept.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

#include "../pinned_decks.hpp"
#include "../solvers/run_deck.hpp"
#include "common/error.hpp"

namespace {

// The coarse hydraulic finger in its compressible material (../pinned_decks.hpp).
const std::vector<std::string> kSmallFinger =
    hs_test::compressible_finger({"mesh.parameters.h=0.006", "control.steps_per_target=2"});

int world_rank() {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
}

hs::Config finger(const std::string& tag) {
  std::vector<std::string> overrides = kSmallFinger;
  overrides.push_back("output.folder=" + hs_test::out_folder(tag));
  hs::Config config =
      hs::parse_deck(std::string(HYDROSOFT_SOURCE_DIR) + "/input/finger_hydraulic.yaml", overrides);
  config.control->targets_from_stdin = true;
  return config;
}

// Runs the small hydraulic finger with `input` as its standard input; the JSON lines it
// writes (rank 0) go to `written`. Returns the summary (complete on rank 0).
// With `writable` >= 0, only that many lines can be written, as to a client that then closes
// its end of standard output.
nlohmann::json run_interactive(const std::string& input, std::vector<nlohmann::json>& written,
                               const std::string& tag, int writable = -1,
                               std::function<void(Vec, int)> after_steps = {},
                               const std::vector<std::string>& overrides = {}) {
  std::istringstream in(input);
  hs::InteractiveIo io;
  io.after_steps = std::move(after_steps);
  io.input = &in;
  io.write_line = [&, writable](const std::string& line) {
    if (writable >= 0 && static_cast<int>(written.size()) >= writable) return false;
    written.push_back(nlohmann::json::parse(line));
    return true;
  };
  hs::Config config = finger(tag);
  if (!overrides.empty()) {
    std::vector<std::string> all = kSmallFinger;
    all.insert(all.end(), overrides.begin(), overrides.end());
    all.push_back("output.folder=" + hs_test::out_folder(tag));
    config =
        hs::parse_deck(std::string(HYDROSOFT_SOURCE_DIR) + "/input/finger_hydraulic.yaml", all);
    config.control->targets_from_stdin = true;
  }
  return hs::run_simulation(config, MPI_COMM_WORLD, io);
}

std::string error_of(const nlohmann::json& line) {
  return line.contains("error") ? line["error"].get<std::string>() : "(no error)";
}

TEST(Interactive, BadLinesAreAnsweredWithAnErrorAndTheLoopGoesOn) {
  const std::string huge(1 << 20, 'x');
  const std::vector<std::string> lines = {
      "0.09 0 -0.012",        // 1: answered
      "1 2",                  // 2: two numbers
      "a b c",                // 3: not numbers
      "nan 0 0",              // 4
      "0 inf 0",              // 5
      "0.09 0 1e300",         // 6: finite, but no answer can be computed
      "",                     // 7: empty
      "nosuch 0.09 0 -0.01",  // 8: unknown effector
      huge,                   // 9: a megabyte
      "tip 0.09 0 -0.008",    // 10: answered
  };
  std::string input;
  for (const auto& line : lines) input += line + "\n";
  std::vector<nlohmann::json> written;
  const nlohmann::json summary = run_interactive(input, written, "bad_lines");
  if (world_rank() != 0) return;

  ASSERT_EQ(written.size(), lines.size());  // one JSON line per input line
  for (size_t k = 0; k < written.size(); ++k) EXPECT_EQ(written[k]["line"], k + 1);
  for (size_t k : {0, 9}) {
    ASSERT_TRUE(written[k].contains("answer")) << written[k];
    EXPECT_LT(written[k]["answer"]["error_m"].get<double>(), 3e-3);
  }
  const std::vector<std::pair<size_t, std::string>> reasons = {
      {1, "got 2 words: '1 2'"},
      {2, "coordinate x 'a' is not a finite number"},
      {3, "coordinate x 'nan' is not a finite number"},
      {4, "coordinate y 'inf' is not a finite number"},
      {5, "1e+300 m from the body, farther than 1000 times its size"},
      {6, "empty line"},
      {7, "no effector named 'nosuch'"},
      {8, "line too long"},
  };
  for (const auto& [k, reason] : reasons) {
    EXPECT_FALSE(written[k].contains("answer")) << written[k];
    EXPECT_NE(error_of(written[k]).find(reason), std::string::npos) << error_of(written[k]);
  }
  // The megabyte is quoted by its start and its length, not echoed.
  EXPECT_LT(written[8].dump().size(), 300u);
  EXPECT_NE(error_of(written[8]).find("(1048576 characters)"), std::string::npos);

  // The results are kept: two target sets, one output step each, in summary.json too.
  EXPECT_EQ(summary["input"], nlohmann::json({{"lines", 10},
                                              {"answered", 2},
                                              {"rejected", 8},
                                              {"failed", 0},
                                              {"end", "end of input"},
                                              {"undelivered", 0}}));
  ASSERT_EQ(summary["targets"].size(), 2u);
  EXPECT_EQ(summary["targets"][1]["line"], 10);
  EXPECT_EQ(written[9]["answer"]["step"].get<int>(), written[0]["answer"]["step"].get<int>() + 1);
  std::ifstream file(summary["output"]["folder"].get<std::string>() + "/summary.json");
  ASSERT_TRUE(file.good());
  EXPECT_EQ(nlohmann::json::parse(file)["targets"].size(), 2u);
}

TEST(Interactive, ARefusedLineChangesNothing) {
  // The same two targets without the bad lines in between: the same answer.
  std::vector<nlohmann::json> with_bad, without;
  run_interactive("0.09 0 -0.012\n0.09 0 1e300\n\n1 2 3 4 5\n0.09 0 -0.008\n", with_bad, "with");
  run_interactive("0.09 0 -0.012\n0.09 0 -0.008\n", without, "without");
  if (world_rank() != 0) return;
  ASSERT_EQ(with_bad.size(), 5u);
  ASSERT_EQ(without.size(), 2u);
  const auto& a = with_bad[4]["answer"];
  const auto& b = without[1]["answer"];
  for (int d = 0; d < 3; ++d)
    EXPECT_NEAR(a["reached"][d].get<double>(), b["reached"][d].get<double>(), 1e-12);
  EXPECT_NEAR(a["actuation"][0].get<double>(), b["actuation"][0].get<double>(), 1e-6);
  EXPECT_EQ(a["step"], b["step"]);
}

// A step that fails inside (here its result made NaN on every rank, as an indefinite tangent
// once left a NaN von Mises stress) gets an error line; the session goes on from where the last
// answered line left the robot, and nothing that is not finite is answered or written. In both
// free_solve modes.
TEST(Interactive, AStepThatFailsIsAnsweredByAnErrorLineAndChangesNothing) {
  for (const std::vector<std::string> mode :
       {std::vector<std::string>{}, {"control.free_solve=one_step"}}) {
    const std::string tag = mode.empty() ? "failed_newton" : "failed_one_step";
    const auto poison = [](Vec u, int line) {
      if (line != 2) return;
      PetscInt low = 0, high = 0;
      VecGetOwnershipRange(u, &low, &high);
      if (high > low) VecSetValue(u, low, std::nan(""), INSERT_VALUES);
      VecAssemblyBegin(u);
      VecAssemblyEnd(u);
    };
    std::vector<nlohmann::json> written, plain;
    const nlohmann::json summary = run_interactive("0.09 0 -0.012\n0.09 0 -0.010\n0.09 0 -0.008\n",
                                                   written, tag, -1, poison, mode);
    // The run without the failed line, for the default mode (one run less; the one_step mode
    // puts back its state the same way).
    if (mode.empty()) run_interactive("0.09 0 -0.012\n0.09 0 -0.008\n", plain, tag + "_plain");
    if (world_rank() != 0) continue;
    ASSERT_EQ(written.size(), 3u) << tag;  // one JSON line per input line
    EXPECT_EQ(written[1]["line"], 2);
    EXPECT_FALSE(written[1].contains("answer")) << written[1];
    EXPECT_NE(error_of(written[1]).find("not finite"), std::string::npos) << error_of(written[1]);
    EXPECT_NE(error_of(written[1]).find("nothing changed"), std::string::npos);
    ASSERT_TRUE(written[2].contains("answer")) << written[2];
    const auto& a = written[2]["answer"];
    if (mode.empty()) {
      ASSERT_EQ(plain.size(), 2u);
      const auto& b = plain[1]["answer"];
      for (int d = 0; d < 3; ++d)
        EXPECT_NEAR(a["reached"][d].get<double>(), b["reached"][d].get<double>(), 1e-9);
      EXPECT_NEAR(a["actuation"][0].get<double>(), b["actuation"][0].get<double>(), 1e-3);
    }
    EXPECT_LT(a["error_m"].get<double>(), 3e-3) << tag;  // 2 steps of 5 kPa at most
    EXPECT_EQ(summary["status"], "ok");
    EXPECT_EQ(summary["input"]["answered"], 2);
    EXPECT_EQ(summary["input"]["failed"], 1);
    EXPECT_EQ(summary["targets"].size(), 2u);
    EXPECT_EQ(summary["outputs"], 4 + 2);  // the failed line wrote no output step
  }
}

TEST(Interactive, EndOfInputAtOnceEndsTheRunWithItsStates) {
  std::vector<nlohmann::json> written;
  const nlohmann::json summary = run_interactive("", written, "empty");
  if (world_rank() != 0) return;
  EXPECT_TRUE(written.empty());
  EXPECT_EQ(summary["input"]["lines"], 0);
  EXPECT_TRUE(summary["targets"].empty());
}

// The client reads two answers and closes its end of standard output: the third line is
// stepped, its answer cannot be written, and the session ends there as at the end of its
// input (the lines after it are not read), its results kept as a run's, on every rank.
TEST(Interactive, AClosedStandardOutputEndsTheSessionAndKeepsItsSteps) {
  std::vector<nlohmann::json> written;
  const nlohmann::json summary =
      run_interactive("0.09 0 -0.012\nx\n0.09 0 -0.008\n0.09 0 -0.010\n", written, "closed", 2);
  EXPECT_EQ(summary["input"]["end"], "standard output closed");
  EXPECT_EQ(summary["input"]["lines"], 3);
  EXPECT_EQ(summary["targets"].size(), 2u);
  if (world_rank() != 0) return;
  ASSERT_EQ(written.size(), 2u);
  EXPECT_EQ(summary["input"], nlohmann::json({{"lines", 3},
                                              {"answered", 2},
                                              {"rejected", 1},
                                              {"failed", 0},
                                              {"end", "standard output closed"},
                                              {"undelivered", 1}}));
  EXPECT_EQ(summary["status"], "ok");
  EXPECT_EQ(summary["outputs"], 4 + 2);  // the state's 4 steps, the two target sets
  std::ifstream file(summary["output"]["folder"].get<std::string>() + "/summary.json");
  ASSERT_TRUE(file.good());
  EXPECT_EQ(nlohmann::json::parse(file)["targets"][1]["line"], 3);
}

// output.every: 2 writes every second answered line and the last: the others' answers carry
// `step: null`, the last line's answer goes out before the end of the input is known (null)
// and summary.json numbers it when the run writes it at the end; the written steps hold the
// same fields as with every line written.
TEST(Interactive, OutputEveryWritesEveryNthLineAndTheLast) {
  const std::string input =
      "0.09 0 -0.012\nx\n0.09 0 -0.008\n0.09 0 -0.010\n0.09 0 -0.011\n0.09 0 -0.009\n";
  std::vector<nlohmann::json> sparse, dense;
  const nlohmann::json summary =
      run_interactive(input, sparse, "every2", -1, {}, {"output.every=2"});
  const nlohmann::json all = run_interactive(input, dense, "every1");
  if (world_rank() != 0) return;
  ASSERT_EQ(sparse.size(), 6u);
  ASSERT_EQ(summary["targets"].size(), 5u);
  // Every second of the state's 4 steps, then lines 3 and 5 (sets 2 and 4) and line 6.
  EXPECT_EQ(summary["outputs"], 2 + 3);
  const std::vector<nlohmann::json> steps = {nullptr, 2, nullptr, 3, 4};
  for (size_t i = 0; i < steps.size(); ++i) {
    EXPECT_EQ(summary["targets"][i]["step"], steps[i]) << i;
    const nlohmann::json& answer = sparse[i < 1 ? 0 : i + 1]["answer"];
    EXPECT_EQ(answer["step"], i == 4 ? nlohmann::json(nullptr) : steps[i]) << i;
    // The same answers, to round-off: two runs on 2 ranks need not sum in the same order.
    for (int d = 0; d < 3; ++d)
      EXPECT_NEAR(answer["reached"][d].get<double>(),
                  dense[i < 1 ? 0 : i + 1]["answer"]["reached"][d].get<double>(), 1e-12)
          << i;
  }
  EXPECT_EQ(all["outputs"], 4 + 5);
}

// A NUL in a line: the error quotes the whole line with the NUL written out (before, the
// message ended at the NUL). A subnormal coordinate is a number: the same answer as 0 (to
// round-off; the finger's size is 0.09 m).
TEST(Interactive, ANulIsWrittenOutAndASubnormalIsANumber) {
  std::vector<nlohmann::json> written, plain;
  run_interactive(std::string("0.09 0\0 -0.012\n0.09 1e-320 -0.012\n", 34), written, "nul");
  run_interactive("0.09 0 -0.012\n", plain, "plain");
  if (world_rank() != 0) return;
  ASSERT_EQ(written.size(), 2u);
  EXPECT_EQ(error_of(written[0]),
            "coordinate y '0\\x00' is not a finite number: '0.09 0\\x00 -0.012'");
  ASSERT_TRUE(written[1].contains("answer")) << written[1];
  EXPECT_EQ(written[1]["answer"]["target"][1].get<double>(), 1e-320);
  // Not bit for bit: on 2 ranks the sums of two runs may round in another order.
  const auto reached = written[1]["answer"]["reached"], expected = plain[0]["answer"]["reached"];
  ASSERT_EQ(reached.size(), 3u);
  for (int d = 0; d < 3; ++d)
    EXPECT_NEAR(reached[d].get<double>(), expected[d].get<double>(), 1e-12) << "component " << d;
}

TEST(Interactive, ADeckTargetTooFarStopsTheRunBeforeAnyStep) {
  hs::Config config = finger("deck_target");
  config.control->targets_from_stdin = false;
  config.control->targets[1][0].position = {0.09, 0.0, 1e12};
  std::string message;
  try {
    hs::run_simulation(config, MPI_COMM_WORLD);
  } catch (const hs::InputError& e) {
    message = e.what();
  }
  EXPECT_NE(message.find("finger_hydraulic.yaml: control.targets[1].tip: target (0.09, 0, 1e+12) "
                         "is 1e+12 m from the body"),
            std::string::npos)
      << message;
  EXPECT_FALSE(std::filesystem::exists(hs_test::out_folder("deck_target")));
}

}  // namespace
