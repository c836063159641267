// Reading .msh files written by the test (known topology), order elevation, and the
// errors of load_mesh and require_group: each names the file (or place) and the reason.
#include <gmsh.h>
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "common/error.hpp"
#include "mesh_test_util.hpp"

namespace hs::test {
namespace {

Mesh load(const std::string& file, int order = 1, std::map<std::string, double> parameters = {}) {
  MeshConfig cfg;
  cfg.file = file;
  cfg.order = order;
  cfg.parameters = std::move(parameters);
  return load_mesh(cfg);
}

TEST(Msh, CornerTetrahedronIsReorientedAndItsGroupsKept) {
  TempDir dir;
  const Mesh m = load(corner_tet().write(dir, "corner.msh"));
  ASSERT_EQ(m.num_nodes(), 4);
  ASSERT_EQ(m.num_tets(), 1);
  EXPECT_NEAR(vertex_volume(m, 0), 1.0 / 6, 1e-15);  // positive after reorientation
  EXPECT_EQ(m.volume_names, std::vector<std::string>{"solid"});
  ASSERT_EQ(num_faces(m, "base"), 1);
  EXPECT_EQ(m.surface_tets.at("base"), std::vector<int64_t>{0});
  const Vec3 a = face_area_vector(m, "base", 0);
  EXPECT_LT((a - Vec3(0, 0, -0.5)).norm(), 1e-15);  // area 1/2, out of the body: -z
  ASSERT_EQ(m.node_groups.at("apex").size(), 1u);
  EXPECT_EQ(node(m, m.node_groups.at("apex")[0]), Vec3(0, 0, 1));
  EXPECT_EQ(m.node_groups.at("base").size(), 3u);
  EXPECT_EQ(m.node_groups.at("solid").size(), 4u);
}

TEST(Msh, FirstOrderFileElevatedToP2) {
  TempDir dir;
  const Mesh m = load(corner_tet().write(dir, "corner.msh"), 2);
  ASSERT_EQ(m.order, 2);
  ASSERT_EQ(m.num_nodes(), 10);
  const int pairs[6][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 0}, {3, 2}, {3, 1}};
  for (int e = 0; e < 6; ++e) {
    const Vec3 mid = 0.5 * (node(m, m.tets[pairs[e][0]]) + node(m, m.tets[pairs[e][1]]));
    EXPECT_LT((node(m, m.tets[4 + e]) - mid).norm(), 1e-15);
  }
  EXPECT_NEAR(p2_volume(m, 0), 1.0 / 6, 1e-15);
  EXPECT_EQ(m.node_groups.at("base").size(), 6u);  // 3 vertices and 3 edge nodes
  for (int64_t n : m.node_groups.at("base")) EXPECT_EQ(node(m, n)[2], 0.0);
}

TEST(Msh, SecondOrderFileKeptAsIsOrReducedToP1) {
  TempDir dir;
  MshFile f = corner_tet();
  // Tet10 in gmsh order; the edge node of (0, 1) sits off its midpoint (a curved edge).
  f.nodes.insert(
      f.nodes.end(),
      {{0.5, 0.1, 0}, {0.5, 0.5, 0}, {0, 0.5, 0}, {0, 0, 0.5}, {0, 0.5, 0.5}, {0.5, 0, 0.5}});
  f.blocks = {{3, 11, {{1, 2, 3, 4, 5, 6, 7, 8, 9, 10}}}};
  f.group_of_dim = {{3, "solid"}};
  const std::string path = f.write(dir, "p2.msh");
  const Mesh p2 = load(path, 2);
  ASSERT_EQ(p2.num_nodes(), 10);
  EXPECT_EQ(node(p2, p2.tets[4]), Vec3(0.5, 0.1, 0));  // not moved back to the midpoint
  const Mesh p1 = load(path, 1);
  EXPECT_EQ(p1.num_nodes(), 4);
  EXPECT_NEAR(vertex_volume(p1, 0), 1.0 / 6, 1e-15);
}

TEST(Msh, RefinedFileSplitsIntoEight) {
  TempDir dir;
  MeshConfig cfg;
  cfg.file = corner_tet().write(dir, "corner.msh");
  cfg.refine = 1;
  for (int order : {1, 2}) {
    cfg.order = order;
    const Mesh m = load_mesh(cfg);
    EXPECT_EQ(m.num_tets(), 8);
    EXPECT_EQ(m.num_nodes(), order == 1 ? 10 : 35);
    EXPECT_NEAR(mesh_volume(m), 1.0 / 6, 1e-15);
    EXPECT_EQ(num_faces(m, "base"), 4);
  }
}

TEST(Msh, InteriorSurfaceFacesTheLowerTetrahedron) {
  TempDir dir;
  MshFile f;  // two tetrahedra sharing the face z = 0; tet 0 lies above it
  f.nodes = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, -1}};
  f.blocks = {{2, 2, {{1, 2, 3}}}, {3, 4, {{1, 2, 3, 4}, {1, 3, 2, 5}}}};
  f.group_of_dim = {{2, "interface"}, {3, "solid"}};
  const Mesh m = load(f.write(dir, "interface.msh"));
  EXPECT_EQ(m.surface_tets.at("interface"), std::vector<int64_t>{0});
  EXPECT_LT((face_area_vector(m, "interface", 0) - Vec3(0, 0, -0.5)).norm(), 1e-15);
}

TEST(Msh, NoVolumeGroupGivesTheDefaultBody) {
  TempDir dir;
  MshFile f = corner_tet();
  f.group_of_dim.erase(3);
  const Mesh m = load(f.write(dir, "nogroup.msh"));
  EXPECT_EQ(m.volume_names, std::vector<std::string>{"body"});
  EXPECT_EQ(m.node_groups.at("body").size(), 4u);
}

TEST(Msh, GmshWrittenFileReadsLikeItsSource) {
  TempDir dir;
  const std::string msh = dir.file("block.msh");
  gmsh::initialize(0, nullptr, false);
  gmsh::option::setNumber("General.Terminal", 0);
  gmsh::open(source_mesh("block.geo"));
  gmsh::model::mesh::generate(3);
  gmsh::write(msh);
  gmsh::finalize();
  const Mesh from_geo = load_geo("block.geo", {});
  const Mesh from_msh = load(msh);
  EXPECT_EQ(from_msh.tets, from_geo.tets);
  ASSERT_EQ(from_msh.x.size(), from_geo.x.size());
  for (size_t i = 0; i < from_geo.x.size(); ++i)  // ASCII .msh keeps 16 digits
    EXPECT_NEAR(from_msh.x[i], from_geo.x[i], 1e-15);
  EXPECT_EQ(from_msh.surfaces, from_geo.surfaces);
  EXPECT_EQ(from_msh.node_groups, from_geo.node_groups);
}

TEST(MeshErrors, MissingFileNamesIt) {
  expect_input_error([] { load("/nonexistent/folder/part.msh"); },
                     {"/nonexistent/folder/part.msh", "cannot open"});
  expect_input_error([] { load("/nonexistent/folder/part.geo"); }, {"part.geo", "cannot open"});
}

TEST(MeshErrors, FileWithoutTetrahedra) {
  TempDir dir;
  MshFile f;
  f.nodes = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  f.blocks = {{2, 2, {{1, 2, 3}}}};
  const std::string path = f.write(dir, "flat.msh");
  expect_input_error([&] { load(path); }, {path, "no tetrahedra"});
}

TEST(MeshErrors, UnsupportedElementType) {
  TempDir dir;
  MshFile f;
  f.nodes = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
             {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  f.blocks = {{3, 5, {{1, 2, 3, 4, 5, 6, 7, 8}}}};
  const std::string path = f.write(dir, "hex.msh");
  expect_input_error([&] { load(path); }, {path, "unsupported 3D element type", "Hexahedron"});
}

TEST(MeshErrors, GarbageFile) {
  TempDir dir;
  const std::string path = dir.file("garbage.msh");
  std::ofstream(path) << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\nthis is not a mesh\n";
  expect_input_error([&] { load(path); }, {path});
}

TEST(MeshErrors, SurfaceTriangleThatBoundsNoTetrahedron) {
  TempDir dir;
  MshFile f;  // two tetrahedra on the face (1, 2, 3); (1, 4, 5) is no face of either
  f.nodes = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, -1}};
  f.blocks = {{2, 2, {{1, 4, 5}}}, {3, 4, {{1, 2, 3, 4}, {1, 3, 2, 5}}}};
  f.group_of_dim = {{2, "loaded"}, {3, "solid"}};
  const std::string path = f.write(dir, "twotets.msh");
  expect_input_error([&] { load(path); }, {path, "'loaded'", "bounds no tetrahedron"});
}

TEST(MeshErrors, UnnamedGroupAndUngroupedVolume) {
  TempDir dir;
  const std::string unnamed = dir.file("unnamed.geo");
  std::ofstream(unnamed) << "SetFactory(\"OpenCASCADE\");\nBox(1) = {0, 0, 0, 1, 1, 1};\n"
                            "Physical Volume(7) = {1};\n";
  expect_input_error([&] { load(unnamed); }, {unnamed, "no name"});
  const std::string two = dir.file("two.geo");
  std::ofstream(two) << "SetFactory(\"OpenCASCADE\");\nBox(1) = {0, 0, 0, 1, 1, 1};\n"
                        "Box(2) = {2, 0, 0, 1, 1, 1};\nPhysical Volume(\"named\") = {1};\n";
  expect_input_error([&] { load(two); }, {two, "no named volume group"});
}

TEST(MeshErrors, ParametersMustBeDefineConstants) {
  TempDir dir;
  const std::string plain = dir.file("plain.geo");
  std::ofstream(plain) << "h = 0.5;\nSetFactory(\"OpenCASCADE\");\nBox(1) = {0, 0, 0, 1, 1, 1};\n"
                          "MeshSize{ PointsOf{ Volume{1}; } } = h;\n";
  expect_input_error([&] { load(plain, 1, {{"h", 0.25}}); }, {plain, "'h'", "DefineConstant"});
  // The same file with DefineConstant takes the value: a finer mesh.
  const std::string defined = dir.file("defined.geo");
  std::ofstream(defined)
      << "DefineConstant[ h = 0.5 ];\nSetFactory(\"OpenCASCADE\");\n"
         "Box(1) = {0, 0, 0, 1, 1, 1};\nMeshSize{ PointsOf{ Volume{1}; } } = h;\n";
  EXPECT_GT(load(defined, 1, {{"h", 0.25}}).num_tets(), 2 * load(defined).num_tets());
  const std::string sphere = source_mesh("lame_sphere.geo");
  expect_input_error([&] { load(sphere, 1, {{"hh", 0.3}}); }, {sphere, "'hh'", "does not occur"});
  // Found by the fuzz harness: 'A' for 'a' passed because a comment of the file starts with "A";
  // comments and strings do not count.
  expect_input_error([&] { load(sphere, 1, {{"A", 1.0}}); }, {sphere, "'A'", "does not occur"});
  expect_input_error(
      [&] {
        load(sphere, 1, {{"need", 1.0}});
      },
      {sphere, "'need'", "does not occur"});
  expect_input_error(
      [&] {
        load(sphere, 1, {{"Mesh.MeshSizeMax", 0.3}});
      },
      {"not a .geo identifier"});
  // Found by the fuzz harness: a carriage return in the name split the message in two lines.
  expect_input_error(
      [&] {
        load(sphere, 1, {{"\rb", 0.3}});
      },
      {sphere, "'\\rb' is not a .geo identifier"});
}

TEST(MeshErrors, BadConfiguration) {
  const std::string block = source_mesh("block.geo");
  expect_input_error([&] { load(block, 3); }, {block, "order"});
  TempDir dir;
  const std::string msh = corner_tet().write(dir, "corner.msh");
  expect_input_error([&] { load(msh, 1, {{"h", 1}}); }, {msh, ".geo files only"});
  const std::string stl = dir.file("part.stl");
  std::ofstream(stl) << "solid x\nendsolid x\n";
  expect_input_error([&] { load(stl); }, {stl, "unknown mesh file type"});
}

TEST(RequireGroup, NamesTheMissingGroupAndThePlace) {
  TempDir dir;
  const Mesh m = load(corner_tet().write(dir, "corner.msh"));
  EXPECT_NO_THROW(require_group(m, "base", "deck.yaml: boundary[0]"));
  expect_input_error([&] { require_group(m, "lid", "deck.yaml: boundary[0]"); },
                     {"deck.yaml: boundary[0]", "'lid'", "apex, base, solid"});
}

}  // namespace
}  // namespace hs::test
