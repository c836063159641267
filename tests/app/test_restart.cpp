// Checkpoints and --restart (docs/output.md, "Checkpoints and restarts"): a run killed
// (SIGKILL) or stopped (SIGTERM) after a checkpoint and restarted from it, on 1 rank and on
// 2, ends with the displacements of an uninterrupted run to 1e-8 relative: static load
// stepping, dynamics, and the states of a hydraulic cavity deck, statically and in time. A
// checkpoint of another deck or other deck values, or one whose state was edited (a step past the
// deck's, a missing or mistyped field), is refused before the output folder is touched.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <signal.h>

#include <cmath>
#include <functional>
#include <nlohmann/json.hpp>

#include "../deck/temp_folder.hpp"
#include "../pinned_decks.hpp"
#include "restart_test_util.hpp"

namespace {
namespace test_restart {

namespace fs = std::filesystem;
using namespace hs::testing;

const std::string kSource = HYDROSOFT_SOURCE_DIR;

struct Case {
  std::string name, deck, args;
  double tolerance = 1e-8;  // of the restarted run's displacement against the uninterrupted
};

std::ostream& operator<<(std::ostream& out, const Case& c) { return out << c.name; }

// Small and short, but long enough that a signal after the first checkpoint finds it going.
const Case kStatic{"static", "cantilever_gravity",
                   "--set mesh.order=1 --set materials[0].model=neo_hookean "
                   "--set materials[0].E=2e5 --set time.steps=20"};
const Case kDynamic{"dynamic", "cantilever_dynamic",
                    "--set mesh.order=1 --set time.dt=0.1 --set time.end_time=2.0 "
                    "--set output.every=1"};
// The cylinders are the coarse compressible one of ../pinned_decks.hpp.
const Case kStates{"states", "cylinder_water",
                   hs_test::coarse_cylinder_args() + "--set states[1].steps=20"};
// Incompressible silicone (nu = 0.5): the volume multipliers are part of the state. Without
// them the restart would rebuild them, to 1.4e-9 of the uninterrupted run; with them it
// repeats its arithmetic (1e-14).
const Case kIncompressible{
    "incompressible", "cylinder_air",
    hs_test::coarse_cylinder_args() + "--set materials[0].nu=0.5 --set states[1].steps=20", 1e-12};
// The same on P2, whose F-bar elements keep a multiplier each (the checkpoint's element
// field): without them the restart would raise them again, to 1.4e-12 of the uninterrupted
// run; with them it repeats its arithmetic (3e-15).
const Case kIncompressibleP2{
    "incompressible_p2", "cylinder_air",
    hs_test::coarse_cylinder_args() +
        "--set materials[0].nu=0.5 --set mesh.order=2 --set states[1].steps=6",
    1e-13};
// The water cylinder in dynamics: its weight ramps in, then 3 kPa, over 25 time steps.
const Case kDynamicStates{"dynamic_states", "cylinder_water",
                          hs_test::coarse_cylinder_args() +
                              "--set 'time={type: dynamic, dt: 0.002, end_time: 0.05}' "
                              "--set 'states=[{name: rest, time: 0.02}, {name: inflated, time: "
                              "0.04, cavities: {cavity: {pressure: 3000}}}]' --set output.every=1"};

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
  EXPECT_LT(d1, c.tolerance);
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
  EXPECT_LT(d2, c.tolerance);
  std::cout << "[ restart  ] " << c.name << ": 1 rank after SIGKILL " << d1
            << ", 2 ranks after SIGTERM " << d2 << " (max |du| / max |u|)" << std::endl;
}

INSTANTIATE_TEST_SUITE_P(Decks, Restart,
                         ::testing::Values(kStatic, kDynamic, kStates, kDynamicStates,
                                           kIncompressible, kIncompressibleP2),
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

// Replaces the JSON state of a checkpoint file by what `edit` makes of it, as anyone can (the
// state is text in an attribute).
void tamper(const std::string& path, const std::function<void(nlohmann::json&)>& edit) {
  nlohmann::json state = checkpoint_state(path);
  ASSERT_FALSE(state.is_null()) << path;
  edit(state);
  const std::string text = state.dump();
  const hid_t access = H5Pcreate(H5P_FILE_ACCESS);
  H5Pset_libver_bounds(access, H5F_LIBVER_V18, H5F_LIBVER_LATEST);
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, access);
  ASSERT_GE(file, 0) << path;
  H5Adelete(file, "state");
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, text.size());
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t a = H5Acreate2(file, "state", type, space, H5P_DEFAULT, H5P_DEFAULT);
  EXPECT_GE(H5Awrite(a, type, text.data()), 0);
  H5Aclose(a);
  H5Sclose(space);
  H5Tclose(type);
  H5Fclose(file);
  H5Pclose(access);
}

struct Tampering {
  std::string what;                           // shown when the case fails
  std::function<void(nlohmann::json&)> edit;  // of the state
  std::string message;                        // after "--restart: FILE: "
};

// Each tampered copy of `original` given to `c` with `args` is refused with exit status 2 and
// one line naming the file, the field and the reason, before the output folder is touched.
void expect_refused(const Case& c, const std::string& args, const std::string& original,
                    const std::vector<Tampering>& cases) {
  TempFolder tmp;
  const std::string copy = (tmp.path() / "checkpoint.h5").string();
  const std::string err = (tmp.path() / "err").string(), out = (tmp.path() / "out").string();
  for (const Tampering& t : cases) {
    fs::copy_file(original, copy, fs::copy_options::overwrite_existing);
    tamper(copy, t.edit);
    fs::remove(err);
    Case tampered = c;
    tampered.args += " " + args;
    EXPECT_EQ(run(command(tampered, out, "--restart " + copy, err)), 2) << t.what << text_of(err);
    EXPECT_EQ(text_of(err), "hydrosoft: error: --restart: " + copy + ": " + t.message + "\n")
        << t.what;
    for (const char* suffix : {"", ".partial", ".lock"})
      EXPECT_FALSE(fs::exists(out + suffix)) << t.what;
  }
}

// Before: a step of 25, -5 or 2^62 of 20 ran nothing and ended "ok" (exit status 0, no
// output step, the displacement of the checkpoint's step as the result); a key missing or of
// another type ended in a raw "[json.exception...]" without the file.
TEST(RestartRefused, ATamperedCheckpointNamesTheFieldBeforeAnyWork) {
  TempFolder tmp;
  const std::string err = (tmp.path() / "err").string();
  Case few = kStatic;
  few.args += " --set time.steps=4";
  const std::string folder = (tmp.path() / "static").string();
  ASSERT_EQ(run(command(few, folder, kCheckpoints, err)), 0) << text_of(err);  // at step 3
  const std::string steps =
      "position.step: must be an integer from 1 to 4 (this deck's load "
      "steps), got ";
  expect_refused(kStatic, "--set time.steps=4", folder + "/checkpoint.h5",
                 {{"step 25", [](auto& s) { s["position"]["step"] = 25; }, steps + "25"},
                  {"step -5", [](auto& s) { s["position"]["step"] = -5; }, steps + "-5"},
                  {"step 2^62", [](auto& s) { s["position"]["step"] = int64_t{1} << 62; },
                   steps + "4611686018427387904"},
                  {"step text", [](auto& s) { s["position"]["step"] = "3"; }, steps + "\"3\""},
                  {"no load factor", [](auto& s) { s["position"].erase("load_factor"); },
                   "position.load_factor: missing"},
                  {"load factor", [](auto& s) { s["position"]["load_factor"] = 0.9; },
                   "position.load_factor: must be step 3's, 0.75, got 0.9"},
                  {"last", [](auto& s) { s["position"]["last"] = true; },
                   "position.last: must be false at this step of this deck"},
                  {"stats", [](auto& s) { s["stats"]["newton_iterations"] = -1; },
                   "stats.newton_iterations: must be an integer from 0 to 2147483647, got -1"},
                  {"nodes", [](auto& s) { s["nodes"] = "many"; },
                   "nodes: must be an integer from 1 to 1099511627776, got \"many\""}});

  // A state deck's and a dynamic deck's own fields.
  const std::string states = (tmp.path() / "states").string();
  ASSERT_EQ(run(command(kStates, states, "--set states[1].steps=4 " + kCheckpoints, err)), 0)
      << text_of(err);  // at state 1, increment 2 (the 6th of 8)
  expect_refused(
      kStates, "--set states[1].steps=4", states + "/checkpoint.h5",
      {{"state", [](auto& s) { s["position"]["state"] = 7; },
        "position.state: must be an integer from 0 to 1 (this deck's states), got 7"},
       {"increment", [](auto& s) { s["position"]["increment"] = 0; },
        "position.increment: must be an integer from 1 to 4 (the increments of its state), got 0"},
       {"constraint", [](auto& s) { s["position"]["constraints"][0]["name"] = "other"; },
        "position.constraints[0].name: is 'other', this deck's is 'cavity'"},
       {"ramps", [](auto& s) { s["position"]["stepper"].erase("ramps"); },
        "position.stepper.ramps: missing"},
       {"rest change",
        [](auto& s) {
          s["position"]["stepper"]["rest_change"] = nlohmann::json{1e-6, 2e-6, 3e-6};
        },
        "position.stepper.rest_change: must have 1 entries (this deck's cavities and cables), "
        "has 3"}});
  const std::string dynamic = (tmp.path() / "dynamic").string();
  Case shorter = kDynamic;
  shorter.args += " --set time.end_time=1.0";
  ASSERT_EQ(run(command(shorter, dynamic, kCheckpoints, err)), 0) << text_of(err);  // at step 9
  expect_refused(
      kDynamic, "--set time.end_time=1.0", dynamic + "/checkpoint.h5",
      {{"step", [](auto& s) { s["position"]["step"] = 11; },
        "position.step: must be an integer from 1 to 10 (this deck's time steps), got 11"},
       {"time", [](auto& s) { s["position"]["time"] = 5; },
        "position.time: must be step 9 times time.dt, 0.9, got 5"}});
  // A dynamic state deck's: the state must be its time step's (24 of 25: the second state).
  const std::string in_time = (tmp.path() / "dynamic_states").string();
  ASSERT_EQ(run(command(kDynamicStates, in_time, kCheckpoints, err)), 0) << text_of(err);
  expect_refused(
      kDynamicStates, "", in_time + "/checkpoint.h5",
      {{"state", [](auto& s) { s["position"]["state"] = 0; },
        "position.state: must be 1, the state of time step 24 in this deck"},
       {"ramps", [](auto& s) { s["position"].erase("ramps"); }, "position.ramps: missing"},
       {"work", [](auto& s) { s["position"]["work"] = nlohmann::json::array(); },
        "position.work: must have 1 entries (this deck's cavities and cables), has 0"}});
}

// A field value that is not a number (a damaged or edited file) is refused before any work,
// naming the dataset and the node. Before, the run took the NaN in and cut its first step back
// eight times, to "element 655 is inverted".
TEST(RestartRefused, AFieldValueThatIsNotANumberNamesTheNodeBeforeAnyWork) {
  TempFolder tmp;
  const std::string err = (tmp.path() / "err").string(), out = (tmp.path() / "out").string();
  Case few = kStatic;
  few.args += " --set time.steps=4";
  const std::string folder = (tmp.path() / "static").string();
  ASSERT_EQ(run(command(few, folder, kCheckpoints, err)), 0) << text_of(err);  // at step 3
  const std::string path = folder + "/checkpoint.h5";
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  const hid_t ids = H5Dopen2(file, "/node_ids", H5P_DEFAULT);
  const hid_t set = H5Dopen2(file, "/fields/displacement", H5P_DEFAULT);
  const hid_t space = H5Dget_space(set);
  std::vector<double> u(H5Sget_simple_extent_npoints(space));  // N x 3
  std::vector<int64_t> node(u.size() / 3);
  ASSERT_GE(H5Dread(ids, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, node.data()), 0);
  ASSERT_GE(H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, u.data()), 0);
  u[3 * 7 + 1] = std::nan("");
  const int64_t id = node[7];
  ASSERT_GE(H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, u.data()), 0);
  H5Sclose(space);
  H5Dclose(set);
  H5Dclose(ids);
  H5Fclose(file);
  EXPECT_EQ(run(command(few, out, "--restart " + folder, err)), 2);
  EXPECT_NE(
      text_of(err).find("hydrosoft: error: --restart: " + path + ": /fields/displacement: node " +
                        std::to_string(id) + " holds a value that is not a finite number"),
      std::string::npos)
      << text_of(err);
  for (const char* suffix : {"", ".partial", ".failed", ".lock"})
    EXPECT_FALSE(fs::exists(out + suffix)) << suffix;
}

}  // namespace test_restart
}  // namespace
