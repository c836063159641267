// What loading a mesh tells the user besides its errors (gmsh_io.hpp): a warning naming the
// worst sliver by its element number in the file, and a .geo's Printf lines, which gmsh's
// confined process passes back to the run's standard error.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "mesh/mesh_checks.hpp"
#include "mesh_test_util.hpp"

namespace hs::test {
namespace {
namespace test_mesh_messages {

// Mean ratio of the tetrahedron (0,0,0), (1,0,0), (0,1,0), (1/3,1/3,h), by hand: volume h/6,
// squared edges 1 + 1 + 2 at the base and 2/9 + h^2, 5/9 + h^2, 5/9 + h^2 to the apex, so
// q = 12 (3 V)^(2/3) / (16/3 + 3 h^2).
double flat_tet_quality(double h) { return 12 * std::cbrt(h * h / 4) / (16.0 / 3 + 3 * h * h); }

// The number as the warning writes it (3 significant digits).
std::string three_digits(double value) {
  std::ostringstream s;
  s.precision(3);
  s << value;
  return s.str();
}

// A triangle (element 1), then a regular-ish corner tetrahedron (element 2) and two flat ones
// of heights h2 (element 3) and h3 (element 4), apart from each other.
MshFile three_tets(double h2, double h3) {
  MshFile f;
  auto add_tet = [&](double x0, double h) {
    const int first = static_cast<int>(f.nodes.size()) + 1;
    f.nodes.push_back({x0, 0, 0});
    f.nodes.push_back({x0 + 1, 0, 0});
    f.nodes.push_back({x0, 1, 0});
    f.nodes.push_back({x0 + 1.0 / 3, 1.0 / 3, h});
    return std::vector<int>{first, first + 1, first + 2, first + 3};
  };
  const std::vector<int> corner = add_tet(0, 1), a = add_tet(3, h2), b = add_tet(6, h3);
  f.blocks = {{2, 2, {{corner[0], corner[2], corner[1]}}}, {3, 4, {corner, a, b}}};
  f.group_of_dim = {{2, "base"}, {3, "solid"}};
  return f;
}

Mesh load(const std::string& file) {
  MeshConfig cfg;
  cfg.file = file;
  return load_mesh(cfg);
}

TEST(MeshQualityWarning, NamesTheWorstSliverByItsNumberInTheFileAndCountsThem) {
  const double h_worst = 3e-4, h_other = 1e-3;
  ASSERT_LT(flat_tet_quality(h_worst), 0.01);  // the reported sliver was 0.0057
  ASSERT_LT(flat_tet_quality(h_other), kPoorTetQuality);
  ASSERT_GT(flat_tet_quality(1.0), kPoorTetQuality);
  TempDir dir;
  const std::string path = three_tets(h_other, h_worst).write(dir, "slivers.msh");
  testing::internal::CaptureStderr();
  const Mesh mesh = load(path);  // a warning, not an error
  const std::string said = testing::internal::GetCapturedStderr();
  EXPECT_EQ(mesh.num_tets(), 3);
  const std::string quality = three_digits(flat_tet_quality(h_worst));
  EXPECT_EQ(quality, "0.00635");
  EXPECT_NE(said.find("hydrosoft: warning: " + path + ": element 4 (vertices (6, 0, 0)"),
            std::string::npos)
      << said;
  EXPECT_NE(said.find("has a mean-ratio quality of " + quality +
                      " (1 is regular), and 2 "
                      "tetrahedra are below 0.02"),
            std::string::npos)
      << said;
  EXPECT_EQ(std::count(said.begin(), said.end(), '\n'), 1) << said;  // one line

  // Without tags (an .h5 mesh, a Mesh built in memory), the tetrahedron's index.
  const std::string direct = quality_warning(mesh, "m.msh");
  EXPECT_NE(direct.find("m.msh: tetrahedron 2 (index)"), std::string::npos) << direct;
}

TEST(MeshQualityWarning, NoneForWellShapedTetrahedra) {
  TempDir dir;
  const std::string path = three_tets(0.5, 1.0).write(dir, "fine.msh");
  testing::internal::CaptureStderr();
  load(path);
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
  // The shipped meshes, as gmsh makes them, are far above the threshold.
  testing::internal::CaptureStderr();
  load_geo("cylinder.geo", {});
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
}

std::string cube_geo(const TempDir& dir, const std::string& name, const std::string& after) {
  const std::string path = dir.file(name);
  std::ofstream(path) << "SetFactory(\"OpenCASCADE\");\nBox(1) = {0, 0, 0, 1, 1, 1};\n"
                         "Physical Volume(\"body\") = {1};\nMesh.MeshSizeMax = 0.5;\n"
                      << after;
  return path;
}

TEST(GeoPrintf, ReachesStandardErrorWithTheFileName) {
  TempDir dir;
  const std::string path =
      cube_geo(dir, "talk.geo", "Printf(\"hello %g\", 3);\nPrintf(\"volume %g\", 1 + 1);\n");
  for (const bool trusted : {false, true}) {  // confined or not: the same way back
    MeshConfig cfg;
    cfg.file = path;
    cfg.trust_geo = trusted;
    testing::internal::CaptureStderr();
    EXPECT_GT(load_mesh(cfg).num_tets(), 0);
    EXPECT_EQ(testing::internal::GetCapturedStderr(),
              "hydrosoft: " + path + ": hello 3\nhydrosoft: " + path + ": volume 2\n");
  }
}

TEST(GeoPrintf, ShowsWhatAFailingGeoPrintedBeforeItsError) {
  TempDir dir;
  const std::string path =
      cube_geo(dir, "fails.geo", "Printf(\"size %g\", 0.5);\nError(\"no\");\n");
  testing::internal::CaptureStderr();
  expect_input_error([&] { load(path); }, {path, "no"});
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "hydrosoft: " + path + ": size 0.5\n");
}

TEST(GeoPrintf, ControlCharactersAreWrittenOutAndTheLinesCapped) {
  TempDir dir;
  const std::string path = cube_geo(dir, "loop.geo",
                                    "Printf(\"clear \x1b[2J\");\nFor i In {1 : 500}\n"
                                    "  Printf(\"line %g\", i);\nEndFor\n");
  testing::internal::CaptureStderr();
  load(path);
  const std::string said = testing::internal::GetCapturedStderr();
  EXPECT_NE(said.find("clear \\x1b[2J\n"), std::string::npos) << said.substr(0, 200);
  EXPECT_NE(said.find(": line 199\n"), std::string::npos);
  EXPECT_EQ(said.find(": line 200\n"), std::string::npos);
  EXPECT_NE(said.find("hydrosoft: " + path + ": 301 more lines not shown\n"), std::string::npos);
  EXPECT_EQ(std::count(said.begin(), said.end(), '\n'), kMaxRelayedLines + 1);
}

}  // namespace test_mesh_messages
}  // namespace
}  // namespace hs::test
