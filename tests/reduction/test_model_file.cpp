// The reduced model's file: written and read back whole, and every malformed file refused
// with the file and the reason named.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "common/error.hpp"
#include "reduction/model_file.hpp"

namespace hs {
namespace {

ReducedModel small_model() {
  ReducedModel m;
  m.nodes = 5;
  m.tets = 2;
  m.order = 1;
  m.coordinate_checksum = 1.25;
  m.physics = "0123456789abcdef";
  m.deck = "deck";
  m.actuators = {"cavity"};
  m.lower = {0};
  m.upper = {3e4};
  m.basis = Eigen::MatrixXd::Random(15, 2);
  m.elements = {1};
  m.weights = {2.5};
  m.patches = {0, 4};  // nodes whose nodal-pressure patch terms are sampled
  m.patch_weights = {1.5, 0.5};
  m.training_actuations = Eigen::MatrixXd::Constant(3, 1, 7.0);
  m.training_states = Eigen::MatrixXd::Random(3, 2);
  m.report = {{"held_back", {{"max_effector_error_m", 1e-4}}}};
  return m;
}

class ModelFile : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ =
        std::filesystem::temp_directory_path() / ("hs_model_file_" + std::to_string(::getpid()));
    std::filesystem::create_directories(folder_);
  }
  void TearDown() override { std::filesystem::remove_all(folder_); }
  std::string path(const std::string& name) const { return (folder_ / name).string(); }
  // The InputError's message when reading `m` written to a file.
  std::string refusal(const ReducedModel& m) {
    const std::string p = path("bad.h5");
    write_reduced_model(p, m);
    try {
      read_reduced_model(p);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
  std::filesystem::path folder_;
};

TEST_F(ModelFile, ReadsBackWhatItWrote) {
  const ReducedModel m = small_model();
  write_reduced_model(path("m.h5"), m);
  EXPECT_FALSE(std::filesystem::exists(path("m.h5.tmp")));
  const ReducedModel r = read_reduced_model(path("m.h5"));
  EXPECT_EQ(r.nodes, 5);
  EXPECT_EQ(r.tets, 2);
  EXPECT_EQ(r.physics, m.physics);
  EXPECT_EQ(r.actuators, m.actuators);
  EXPECT_EQ(r.upper, m.upper);
  EXPECT_EQ(r.basis, m.basis);  // exact: doubles stored as doubles
  EXPECT_EQ(r.elements, m.elements);
  EXPECT_EQ(r.weights, m.weights);
  EXPECT_EQ(r.patches, m.patches);
  EXPECT_EQ(r.patch_weights, m.patch_weights);
  EXPECT_EQ(r.training_actuations, m.training_actuations);
  EXPECT_EQ(r.training_states, m.training_states);
  EXPECT_EQ(r.report, m.report);
  // A model of a body without the nodal-pressure element samples no patch.
  ReducedModel elements_only = small_model();
  elements_only.patches.clear();
  elements_only.patch_weights.clear();
  write_reduced_model(path("e.h5"), elements_only);
  EXPECT_TRUE(read_reduced_model(path("e.h5")).patches.empty());
}

TEST_F(ModelFile, RefusesWhatIsNotAModel) {
  auto message = [](const std::string& p) {
    try {
      read_reduced_model(p);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message(path("none.h5")).find("none.h5: cannot be examined: No such file"),
            std::string::npos);
  std::ofstream(path("text.h5")) << "not hdf5";
  EXPECT_NE(message(path("text.h5")).find("not an HDF5 file"), std::string::npos);
  EXPECT_NE(message(folder_.string()).find(folder_.string()), std::string::npos);
}

TEST_F(ModelFile, RefusesContentsNoModelHas) {
  ReducedModel m = small_model();
  m.weights = {-1};
  EXPECT_NE(refusal(m).find("is not a positive number"), std::string::npos);
  m = small_model();
  m.elements = {2};  // of 2 tetrahedra: 0 and 1
  EXPECT_NE(refusal(m).find("is not a tetrahedron of the mesh"), std::string::npos);
  m = small_model();
  m.patches = {0, 5};  // of 5 nodes: 0 to 4
  EXPECT_NE(refusal(m).find("/patches: 5 is not a node of the mesh"), std::string::npos);
  m = small_model();
  m.patch_weights = {1.5, 0};
  EXPECT_NE(refusal(m).find("/patch_weights: the weight of node 4's patch"), std::string::npos);
  m = small_model();
  m.basis(3, 1) = std::nan("");
  EXPECT_NE(refusal(m).find("/basis holds a value that is not finite"), std::string::npos);
  m = small_model();
  m.basis = Eigen::MatrixXd::Ones(12, 2);  // 4 nodes' rows for a 5-node mesh
  EXPECT_NE(refusal(m).find("/basis: 12 x 2 values where the model says 15 x 2"),
            std::string::npos);
  m = small_model();
  m.lower = {4e4};
  EXPECT_NE(refusal(m).find("training envelope of actuator 'cavity' is not a range"),
            std::string::npos);
  m = small_model();
  m.training_states = Eigen::MatrixXd::Ones(3, 3);
  EXPECT_NE(refusal(m).find("/training_states"), std::string::npos);
  EXPECT_NE(refusal(m).find(path("bad.h5")), std::string::npos);
}

}  // namespace
}  // namespace hs
