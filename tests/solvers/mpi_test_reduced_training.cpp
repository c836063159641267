// A reduced model trained on several ranks (docs/reduced_models.md): the full solves run on
// every rank and the model is built on rank 0's copy of the whole body; it is the model that
// one rank trains (the same snapshots to the solver's tolerance), and it answers as that one.
#include <gtest/gtest.h>

#include <cmath>

#include "../pinned_decks.hpp"
#include "reduction/model_file.hpp"
#include "run_deck.hpp"

namespace {

using hs_test::out_folder;
using hs_test::world_rank;

hs::Config finger(const std::vector<std::string>& given, const std::string& tag) {
  std::vector<std::string> overrides = {"mesh.parameters.h=0.006", "output.progress=false",
                                        "output.folder=" + out_folder(tag)};
  overrides.insert(overrides.end(), given.begin(), given.end());
  return hs::parse_deck(std::string(HYDROSOFT_SOURCE_DIR) + "/input/finger_pneumatic.yaml",
                        hs_test::compressible_finger(overrides));
}

// The training's summary on every rank: on all ranks of `comm`, or on rank 0 alone (MPI_COMM_SELF).
nlohmann::json train(const std::string& model, const std::string& tag, MPI_Comm comm) {
  hs::Config config = finger({}, tag);
  hs::TrainingConfig training;
  training.output = model;
  training.samples = 9;
  config.training = training;
  nlohmann::json summary;
  if (comm == MPI_COMM_WORLD || world_rank() == 0) summary = hs::run_simulation(config, comm);
  return hs_test::shared(summary);
}

// The deck's targets answered on rank 0 with `model`, each with the full model's equilibrium.
nlohmann::json answers(const std::string& model, const std::string& tag) {
  nlohmann::json summary;
  if (world_rank() == 0)
    summary = hs::run_simulation(
        finger({"control.reduced_model=" + model, "control.check_equilibrium=true"}, tag),
        MPI_COMM_SELF);
  return hs_test::shared(summary);
}

TEST(ReducedTraining, OnTwoRanksTrainsTheModelOfOneRank) {
  const std::string two = out_folder("two.h5"), one = out_folder("one.h5");
  const nlohmann::json a = train(two, "train_two", MPI_COMM_WORLD);
  const nlohmann::json b = train(one, "train_one", MPI_COMM_SELF);
  EXPECT_EQ(a.at("ranks"), 2);
  EXPECT_EQ(b.at("ranks"), 1);
  const nlohmann::json &ra = a.at("reduction"), &rb = b.at("reduction");
  EXPECT_EQ(ra.at("samples"), 9);
  ASSERT_EQ(ra.at("pod").at("modes"), rb.at("pod").at("modes"));
  const auto& sa = ra.at("pod").at("singular_values");
  const auto& sb = rb.at("pod").at("singular_values");
  ASSERT_EQ(sa.size(), sb.size());
  for (size_t i = 0; i < sa.size(); ++i)  // Newton's 1e-10 of the forces, in the snapshots
    EXPECT_NEAR(sa[i].get<double>(), sb[i].get<double>(), 1e-7 * sa[0].get<double>()) << i;
  const double stated_a = ra.at("held_back").at("max_effector_error_m");
  const double stated_b = rb.at("held_back").at("max_effector_error_m");
  EXPECT_GT(stated_a, 0);
  EXPECT_NEAR(stated_a, stated_b, 0.01 * stated_b);
  // The file written on rank 0 holds the report the run gives, its times included.
  const nlohmann::json in_file = hs::read_reduced_model(two).report;
  EXPECT_EQ(in_file.at("held_back"), ra.at("held_back"));
  EXPECT_EQ(in_file.at("seconds"), ra.at("seconds"));
  EXPECT_GT(in_file.at("seconds").get<double>(), in_file.at("snapshot_seconds").get<double>());

  // Each model's answers within its stated error of the full model's equilibrium, and the two
  // models' answers the same to well within it.
  const nlohmann::json x = answers(two, "use_two"), y = answers(one, "use_one");
  ASSERT_EQ(x.at("targets").size(), 6u);
  for (size_t k = 0; k < 6; ++k) {
    const nlohmann::json &t = x["targets"][k], &u = y["targets"][k];
    double miss2 = 0, apart2 = 0;
    for (int d = 0; d < 3; ++d) {
      miss2 += std::pow(t["reached"][d].get<double>() - t["equilibrium"][d].get<double>(), 2);
      apart2 += std::pow(t["reached"][d].get<double>() - u["reached"][d].get<double>(), 2);
    }
    EXPECT_LE(std::sqrt(miss2), 1.5 * stated_a) << k << ": " << t.dump();
    EXPECT_LT(std::sqrt(apart2), 0.1 * stated_a) << k;
  }
}

}  // namespace
