// SIGKILL at any moment never leaves a half-result where a good one was: a run with
// checkpoints at every step is killed at 5 seeded random moments between its start and its
// end, over an earlier good result in its folder. After each kill the folder holds that
// result byte for byte (or, killed after its commit, the new complete one), readable; no
// .failed folder appears; and a checkpoint left in the staging folder is whole.
#include <gtest/gtest.h>
#include <signal.h>

#include <nlohmann/json.hpp>
#include <random>

#include "../deck/temp_folder.hpp"
#include "restart_test_util.hpp"

namespace {

namespace fs = std::filesystem;
using namespace hs::testing;

// Whether a checkpoint file opens and holds its JSON state.
bool whole_checkpoint(const std::string& path) { return !checkpoint_state(path).is_null(); }

TEST(KillMoments, AnEarlierResultIsAlwaysIntactAndNoHalfResultIsPresented) {
  TempFolder tmp;
  const std::string folder = (tmp.path() / "beam").string(), err = (tmp.path() / "err").string();
  const std::string command =
      std::string(HYDROSOFT_EXE) + " " + HYDROSOFT_SOURCE_DIR +
      "/input/cantilever_gravity.yaml -q --set mesh.order=1 --set materials[0].model=neo_hookean "
      "--set materials[0].E=2e5 --set time.steps=20 --set 'output.checkpoint={every: 1}' "
      "--set output.folder=" +
      folder + " > /dev/null 2>> " + err;
  const auto t0 = std::chrono::steady_clock::now();
  ASSERT_EQ(run(command), 0) << text_of(err);
  const double duration =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const std::string h5 = folder + "/cantilever_gravity.h5", summary = folder + "/summary.json";
  const int steps = last_step(h5).steps;
  ASSERT_EQ(steps, 20);
  std::string good_h5 = text_of(h5), good_summary = text_of(summary);

  std::mt19937 random(20240611);
  std::uniform_real_distribution<double> moment(0.0, 1.1);  // a little past the end too
  int kept = 0, replaced = 0;
  for (int k = 0; k < 5; ++k) {
    const double at = moment(random) * duration;
    const pid_t pid = start(command);
    std::this_thread::sleep_for(std::chrono::duration<double>(at));
    kill(pid, SIGKILL);
    wait_for(pid);
    SCOPED_TRACE("killed at " + std::to_string(at) + " s of " + std::to_string(duration));
    ASSERT_TRUE(fs::exists(summary));
    EXPECT_FALSE(fs::exists(folder + ".failed"));
    const auto result = nlohmann::json::parse(text_of(summary));
    EXPECT_EQ(result["status"], "ok");
    EXPECT_EQ(last_step(h5).steps, steps);  // readable, every step there
    if (text_of(summary) == good_summary) {
      EXPECT_EQ(text_of(h5), good_h5);
      ++kept;
    } else {
      good_h5 = text_of(h5);  // the killed run had committed: its result is the good one now
      good_summary = text_of(summary);
      ++replaced;
    }
    if (fs::exists(folder + ".partial/checkpoint.h5"))
      EXPECT_TRUE(whole_checkpoint(folder + ".partial/checkpoint.h5"));
  }
  std::cout << "[ kills    ] " << kept << " kills left the earlier result, " << replaced
            << " came after the run's commit (run: " << duration << " s)" << std::endl;
}

}  // namespace
