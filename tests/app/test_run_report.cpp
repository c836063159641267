// The lines a run prints when it ends (app/run_report.cpp): made from the summary, with the
// numbers in the units the header names.
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "run_report.hpp"

namespace {

using Json = nlohmann::json;

// The words of the report's line that holds both `a` and `b` (none if no line does).
std::vector<std::string> words_of_line(const std::string& report, const std::string& a,
                                       const std::string& b) {
  std::istringstream lines(report);
  for (std::string line; std::getline(lines, line);)
    if (line.find(a) != std::string::npos && line.find(b) != std::string::npos) {
      std::istringstream in(line);
      std::vector<std::string> words;
      for (std::string w; in >> w;) words.push_back(w);
      return words;
    }
  return {};
}

TEST(RunReport, StatesGiveEachCavitysPressureInKilopascalsAndVolumesInMillilitres) {
  const Json summary = Json::parse(R"({
    "steps": 14, "newton_iterations": 40, "ranks": 2, "time_s": {"total": 1.3},
    "output": {"xdmf": "out/cylinder_air/cylinder_air.xmf"},
    "states": [
      {"name": "rest", "tip": {"group": "tip", "inclination_deg": 10.574, "rotation_deg": 10.6},
       "cavities": [{"name": "cavity", "pressure": 0.0, "volume_ml": 78.98, "added_volume_ml": 0}]},
      {"name": "inflated", "tip": {"group": "tip", "inclination_deg": 8.11, "rotation_deg": 8.2},
       "cavities": [{"name": "cavity", "pressure": 7915.9, "volume_ml": 93.98,
                     "added_volume_ml": 15.0}]}]})");
  const std::string report = hs::run_report(summary);
  EXPECT_NE(report.find("# hydrosoft: done: 14 steps, 40 Newton iterations, 1.30 s on 2 ranks\n"),
            std::string::npos)
      << report;
  EXPECT_NE(report.find("out/cylinder_air/cylinder_air.xmf"), std::string::npos);
  EXPECT_NE(report.find("tip inclination (deg)"), std::string::npos);
  EXPECT_NE(report.find("inflated  8.11"), std::string::npos) << report;
  EXPECT_NE(report.find("8.20"), std::string::npos) << report;    // the rotation
  EXPECT_NE(report.find("7.916"), std::string::npos) << report;   // kPa
  EXPECT_NE(report.find("93.980"), std::string::npos) << report;  // ml
  EXPECT_NE(report.find("15.000"), std::string::npos) << report;
  EXPECT_EQ(report.find("{"), std::string::npos) << "no JSON on the screen";
}

// The sub-steps the cutbacks added are explained on the line that counts the steps.
TEST(RunReport, CutbacksAreCountedBesideTheSteps) {
  const Json summary = Json::parse(R"({"steps": 8, "cutbacks": 7, "newton_iterations": 106})");
  const std::string report = hs::run_report(summary);
  EXPECT_NE(report.find("done: 8 steps, 7 cutbacks, 106 Newton iterations, "), std::string::npos)
      << report;
}

TEST(RunReport, TipDisplacementInMillimetresAndReactionsPerBoundaryGroup) {
  const Json summary = Json::parse(R"({"steps": 3, "newton_iterations": 9,
    "reactions_N": {"base": [0.0, 1.0817425, -2.5e-14], "x0": [-3.25, 0, 0]},
    "states": [{"name": "inflated", "tip": {"group": "tip", "inclination_deg": 0,
                "rotation_deg": 17.2, "displacement_m": [0, -0.019, 0.0001],
                "displacement_magnitude_m": 0.0190026},
                "cavities": [{"name": "cavity", "pressure": 7915.9, "volume_ml": 93.98,
                              "added_volume_ml": 15.0}]}]})");
  const std::string report = hs::run_report(summary);
  EXPECT_NE(report.find("tip displacement (mm)"), std::string::npos) << report;
  EXPECT_NE(report.find("17.20               19.003"), std::string::npos) << report;
  EXPECT_NE(report.find("boundary group  reaction x (N)  reaction y (N)  reaction z (N)"),
            std::string::npos)
      << report;
  // -2.5e-14 N beside 3.25 N is round-off of zero.
  EXPECT_NE(report.find("base            0               1.08174         0\n"), std::string::npos)
      << report;
  EXPECT_NE(report.find("x0              -3.25"), std::string::npos) << report;
}

TEST(RunReport, CablesGiveTheirForceAndPullInMillimetres) {
  const Json summary = Json::parse(R"({"steps": 8, "newton_iterations": 20,
    "states": [{"name": "pulled", "cavities": [],
                "cables": [{"name": "tendon", "kind": "cable", "length": 0.1, "pull": 0.0042,
                            "force": 1.5}]}]})");
  const std::string report = hs::run_report(summary);
  EXPECT_NE(report.find("force (N)  pull (mm)"), std::string::npos) << report;
  EXPECT_NE(report.find("pulled  tendon  1.5        4.200"), std::string::npos) << report;
  EXPECT_EQ(report.find("tendon  -"), std::string::npos) << "a cable is not listed as a cavity";
}

TEST(RunReport, TargetsGiveMillimetresAndTheError) {
  const Json summary = Json::parse(R"({
    "steps": 4, "newton_iterations": 9, "ranks": 1, "time_s": {"total": 0.5},
    "targets": [{"target": [0.09, 0.0, -0.012], "reached": [0.08997, -0.0004, -0.012],
                 "error_m": 2.5e-4, "actuation": [21759.1]},
                {"target": [0.09, 0.0, 0.03], "reached": [0.09, 0.0, 0.01],
                 "error_m": null, "actuation": [30000]}]})");
  const std::string report = hs::run_report(summary);
  EXPECT_NE(report.find("# hydrosoft: done: 2 targets, 0.50 s on 1 rank\n"), std::string::npos)
      << report;
  EXPECT_NE(report.find("90.00, 0.00, -12.00"), std::string::npos) << report;
  EXPECT_NE(report.find("89.97, -0.40, -12.00"), std::string::npos) << report;
  EXPECT_NE(report.find("0.250"), std::string::npos) << report;
  EXPECT_NE(report.find("2.176e+04"), std::string::npos) << report;
}

// A contact-force effector's target and reach are forces: printed in N, marked as such.
TEST(RunReport, ContactForceTargetsGiveNewtons) {
  const Json summary = Json::parse(R"({
    "steps": 2, "newton_iterations": 9, "ranks": 1, "time_s": {"total": 0.5},
    "targets": [{"target": [0.09, 0.0, -0.012], "reached": [0.08997, -0.0004, -0.012],
                 "error_m": 2.5e-4, "actuation": [21759.1]},
                {"target": [0, -0.06, 0], "reached": [0.004566, -0.0599, -0.005119],
                 "error_N": 1e-4, "actuation": [21759.1]}]})");
  const std::string report = hs::run_report(summary);
  EXPECT_NE(report.find("target (mm or N)"), std::string::npos) << report;
  EXPECT_NE(report.find("90.00, 0.00, -12.00"), std::string::npos) << report;
  const auto force = words_of_line(report, "-0.06", "-0.0599");
  ASSERT_FALSE(force.empty()) << report;
  EXPECT_EQ(force[3], "N") << report;  // the target
  EXPECT_NE(report.find("0.004566, -0.0599, -0.005119 N  0.0001 N"), std::string::npos) << report;
}

// A value within 1e-10 of its column's largest magnitude is round-off of zero: printed as 0 in
// the column's format, never as "1.455e-11" Pa beside 2.2e4 Pa or "-0.000" kPa. Each actuator
// is its own column (Pa and N share the cell), and a column of small values alone keeps them.
TEST(RunReport, RoundOffOfZeroIsPrintedAsZeroAgainstItsColumn) {
  const Json targets = Json::parse(R"({"steps": 4, "newton_iterations": 9,
    "targets": [{"target": [0.09, 0.0, -0.012], "reached": [0.09, -1e-9, -0.012],
                 "error_m": 0, "actuation": [21759.1, 0.75, 2e-12]},
                {"target": [0.09, 0.0, -0.01], "reached": [0.09, 0.0, -0.01],
                 "error_m": 0, "actuation": [1.455e-11, -3e-11, 3e-12]}]})");
  const std::string controlled = hs::run_report(targets);
  EXPECT_NE(controlled.find("2.176e+04, 0.75, 2e-12\n"), std::string::npos) << controlled;
  EXPECT_NE(controlled.find("0, 0, 3e-12\n"), std::string::npos) << controlled;
  EXPECT_NE(controlled.find("90.00, 0.00, -12.00"), std::string::npos) << controlled;
  EXPECT_EQ(controlled.find("e-11"), std::string::npos) << controlled;
  EXPECT_EQ(controlled.find("-0.00"), std::string::npos) << controlled;  // reached y: -1e-6 mm

  const Json states = Json::parse(R"({"steps": 4, "newton_iterations": 9,
    "states": [{"name": "inflated", "cavities": [{"name": "cavity", "pressure": 20000.0,
                 "volume_ml": 2.5, "added_volume_ml": 0.5}],
                "cables": [{"name": "tendon", "pull": 0.001, "force": 2.5}]},
               {"name": "deflated", "cavities": [{"name": "cavity", "pressure": -4.5e-13,
                 "volume_ml": 2.0, "added_volume_ml": 0}],
                "cables": [{"name": "tendon", "pull": 0, "force": 1e-14}]}]})");
  const std::string report = hs::run_report(states);
  const auto cavity = words_of_line(report, "deflated", "cavity");
  ASSERT_EQ(cavity.size(), 8u) << report;
  EXPECT_EQ(cavity[5], "0.000") << report;  // p (kPa)
  const auto cable = words_of_line(report, "deflated", "tendon");
  ASSERT_EQ(cable.size(), 4u) << report;
  EXPECT_EQ(cable[2], "0") << report;  // force (N)
  EXPECT_EQ(report.find("-0.000"), std::string::npos) << report;
}

TEST(RunReport, VerificationFiguresAreListed) {
  const Json summary = Json::parse(R"({"steps": 1, "newton_iterations": 6,
    "error": {"l2_relative": 0.0659667, "l2_absolute": 5.4e-8}})");
  const std::string report = hs::run_report(summary);
  EXPECT_NE(report.find("l2_relative  0.0659667"), std::string::npos) << report;
  EXPECT_NE(report.find("l2_absolute  5.4e-08"), std::string::npos) << report;
}

}  // namespace
