// One deck, run by the executable on 1, 2 and 3 ranks: the displacements it writes agree to
// 1e-10 of their largest value at every node (matched by /mesh/node_ids, the rows' numbers in
// the mesh file), each rank writing its own rows; a control deck's targets, reached positions
// to 1e-9 m and actuations to 1e-4 Pa. Once with the .geo meshed on rank 0 and sent out in
// blocks, once from an .h5 mesh written by `hydrosoft mesh` and read in blocks.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "../deck/temp_folder.hpp"
#include "text_file.hpp"

namespace {
namespace test_rank_independence {

using hs::testing::TempFolder;
const std::string kSource = HYDROSOFT_SOURCE_DIR;

template <class T>
std::vector<T> read(hid_t file, const std::string& name, hid_t type) {
  const hid_t set = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  EXPECT_GE(set, 0) << name;
  const hid_t space = H5Dget_space(set);
  std::vector<T> out(H5Sget_simple_extent_npoints(space));
  H5Dread(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data());
  H5Sclose(space);
  H5Dclose(set);
  return out;
}

// The last step's displacement, 3 per node in the mesh file's numbering.
std::vector<double> displacement(const std::string& h5) {
  const hid_t file = H5Fopen(h5.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  EXPECT_GE(file, 0) << h5;
  int last = 0;
  while (H5Lexists(file, ("/step_" + std::to_string(last + 1)).c_str(), H5P_DEFAULT) > 0) ++last;
  const auto ids = read<int64_t>(file, "/mesh/node_ids", H5T_NATIVE_INT64);
  const auto u =
      read<double>(file, "/step_" + std::to_string(last) + "/displacement", H5T_NATIVE_DOUBLE);
  H5Fclose(file);
  std::vector<double> by_id(u.size(), NAN);
  for (size_t row = 0; row < ids.size(); ++row)
    for (int d = 0; d < 3; ++d) by_id[3 * ids[row] + d] = u[3 * row + d];
  return by_id;
}

int run(const std::string& command) { return std::system((command + " > /dev/null 2>&1").c_str()); }

// The control loop's answers: every target's reached position and actuation as on 1 rank.
void expect_same_targets(const nlohmann::json& first, const nlohmann::json& got, int np) {
  ASSERT_EQ(got["targets"].size(), first["targets"].size()) << np << " ranks";
  for (size_t k = 0; k < first["targets"].size(); ++k) {
    const auto &a = first["targets"][k], &b = got["targets"][k];
    for (int d = 0; d < 3; ++d)
      EXPECT_NEAR(b["reached"][d].get<double>(), a["reached"][d].get<double>(), 1e-9)
          << "target " << k << " on " << np << " ranks";
    ASSERT_EQ(b["actuation"].size(), a["actuation"].size());
    for (size_t i = 0; i < a["actuation"].size(); ++i)
      EXPECT_NEAR(b["actuation"][i].get<double>(), a["actuation"][i].get<double>(), 1e-4)
          << "target " << k << " on " << np << " ranks";
  }
}

void expect_rank_independent(const std::string& deck, const std::string& name,
                             const std::string& extra, const TempFolder& tmp, size_t targets = 0) {
  std::vector<double> first;
  nlohmann::json first_summary;
  for (int np = 1; np <= 3; ++np) {
    const std::string out = (tmp.path() / (name + std::to_string(np))).string();
    ASSERT_EQ(run(std::string(HYDROSOFT_MPIEXEC) + " -np " + std::to_string(np) + " " +
                  HYDROSOFT_EXE + " " + deck + " " + extra + " --set output.folder=" + out),
              0)
        << deck << " on " << np << " ranks";
    const std::vector<double> u = displacement(out + "/" + name + ".h5");
    const nlohmann::json summary =
        nlohmann::json::parse(hs::testing::text_of(out + "/summary.json"));
    if (np == 1) {
      if (targets > 0) ASSERT_EQ(summary["targets"].size(), targets);
      first = u;
      first_summary = summary;
      continue;
    }
    if (targets > 0) expect_same_targets(first_summary, summary, np);
    ASSERT_EQ(u.size(), first.size());
    double scale = 0, worst = 0;
    for (size_t i = 0; i < u.size(); ++i) {
      ASSERT_TRUE(std::isfinite(u[i])) << "entry " << i << " on " << np << " ranks";
      scale = std::max(scale, std::abs(first[i]));
      worst = std::max(worst, std::abs(u[i] - first[i]));
    }
    EXPECT_GT(scale, 0.0);
    EXPECT_LE(worst, 1e-10 * scale) << deck << " on " << np << " ranks";
  }
}

TEST(RankIndependence, HyperelasticSphereMeshedOnRankZero) {
  TempFolder tmp;
  expect_rank_independent(kSource + "/input/neo_hookean_sphere.yaml", "neo_hookean_sphere",
                          "--set mesh.parameters.h=0.5 -snes_rtol 1e-12", tmp);
}

TEST(RankIndependence, HydraulicFingerFromAnH5Mesh) {
  TempFolder tmp;
  const std::string mesh = (tmp.path() / "finger.h5").string();
  ASSERT_EQ(run(std::string(HYDROSOFT_EXE) + " mesh " + kSource + "/input/finger_hydraulic.yaml " +
                mesh + " --set mesh.parameters.h=0.006"),
            0);
  // The finger's deck with the mesh file in place of its .geo source.
  std::ifstream in(kSource + "/input/finger_hydraulic.yaml");
  std::string text, line;
  bool in_mesh = false;
  while (std::getline(in, line)) {
    if (line == "mesh:") {
      text += "mesh:\n  file: " + mesh + "\n";
      in_mesh = true;
      continue;
    }
    if (in_mesh && line.rfind("  ", 0) == 0) continue;
    in_mesh = false;
    text += line + "\n";
  }
  const std::string deck = (tmp.path() / "finger_h5.yaml").string();
  std::ofstream(deck) << text;
  expect_rank_independent(deck, "finger_h5", "--set control.steps_per_target=1", tmp, 6);
}

}  // namespace test_rank_independence
}  // namespace
