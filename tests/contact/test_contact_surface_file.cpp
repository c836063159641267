// A surface obstacle's file as untrusted input (src/contact/surface_file.cpp): the box read
// from binary and ASCII STL (its repeated corners merged) and from OBJ (indices from the
// start or counted back from the end) is the box; every refusal names the file and the
// reason, and a deck with a bad file is refused when it is read, naming its key.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "common/error.hpp"
#include "contact/surface_file.hpp"
#include "deck/config_fingerprint.hpp"
#include "deck/deck.hpp"
#include "surface_test_util.hpp"

namespace {
namespace test_contact_surface_file {

using V3 = Eigen::Vector3d;
namespace fs = std::filesystem;

class SurfaceFile : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = (fs::temp_directory_path() / "hs_surface_test_XXXXXX").string();
    folder_ = mkdtemp(pattern.data());
  }
  void TearDown() override { fs::remove_all(folder_); }
  std::string file(const std::string& name) const { return folder_ + "/" + name; }
  // The message of the refusal of `path`, which must name it.
  std::string refusal(const std::string& path, size_t max_triangles = hs::kMaxSurfaceTriangles) {
    try {
      hs::read_obstacle_surface(path, 1.0, max_triangles);
    } catch (const hs::InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(path), std::string::npos) << what;
      return what;
    }
    ADD_FAILURE() << path << " was accepted";
    return {};
  }
  std::string folder_;
};

const hs_test::Surface kBox = hs_test::box_surface(V3(0.5, 0.25, 0.125), V3(1, 0.5, 0.25));

TEST_F(SurfaceFile, TheBoxInEveryFormatIsTheBox) {
  hs_test::write_stl_binary(file("box.stl"), kBox);
  hs_test::write_stl_ascii(file("ascii.STL"), kBox);
  hs_test::write_obj(file("box.obj"), kBox);
  hs_test::write_obj(file("relative.obj"), kBox, true);
  for (const char* name : {"box.stl", "ascii.STL", "box.obj", "relative.obj"}) {
    const auto s = hs::read_obstacle_surface(file(name), 2.0);
    EXPECT_EQ(s->vertices().size(), 8u) << name;  // STL's 36 corners merged
    ASSERT_EQ(s->num_triangles(), 12u) << name;
    for (size_t t = 0; t < 12; ++t)
      for (int k = 0; k < 3; ++k)
        EXPECT_EQ(s->vertices()[s->triangles()[t][k]], 2.0 * kBox.vertices[kBox.triangles[t][k]])
            << name;
  }
}

TEST_F(SurfaceFile, AMissingOrUnreadableFileIsRefused) {
  EXPECT_NE(refusal(file("none.stl")).find("no such file"), std::string::npos);
  fs::create_directory(file("folder.stl"));
  EXPECT_NE(refusal(file("folder.stl")).find("not a regular file"), std::string::npos);
  std::ofstream(file("box.ply")) << "ply\n";
  EXPECT_NE(refusal(file("box.ply")).find("a .stl or .obj file"), std::string::npos);
}

TEST_F(SurfaceFile, ATruncatedBinaryStlOrAWrongCountIsRefused) {
  hs_test::write_stl_binary(file("box.stl"), kBox);
  std::string bytes;
  {
    std::ifstream in(file("box.stl"), std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  std::ofstream(file("cut.stl"), std::ios::binary) << bytes.substr(0, bytes.size() - 7);
  EXPECT_NE(refusal(file("cut.stl")).find("its facet count 12 needs 84 + 50 x 12"),
            std::string::npos);
  bytes[80] = 13;
  std::ofstream(file("count.stl"), std::ios::binary) << bytes;
  EXPECT_NE(refusal(file("count.stl")).find("facet count 13"), std::string::npos);
}

TEST_F(SurfaceFile, MoreTrianglesThanTheLimitAreRefused) {
  hs_test::write_stl_binary(file("box.stl"), kBox);
  EXPECT_NE(refusal(file("box.stl"), 11).find("12 triangles, beyond the 11"), std::string::npos);
}

TEST_F(SurfaceFile, ANonFiniteOrHugeCoordinateIsRefused) {
  hs_test::Surface s = kBox;
  s.vertices[3](1) = std::nan("");
  hs_test::write_stl_binary(file("nan.stl"), s);
  EXPECT_NE(refusal(file("nan.stl")).find("not a finite number"), std::string::npos);
  hs_test::write_obj(file("nan.obj"), s);
  EXPECT_NE(refusal(file("nan.obj")).find(":6: coordinate 'nan'"), std::string::npos);
  s.vertices[3](1) = 2e6;
  hs_test::write_obj(file("huge.obj"), s);
  EXPECT_NE(refusal(file("huge.obj")).find("vertex 4 at (1, 2000000, 0) m (after scale) is beyond"),
            std::string::npos);
}

TEST_F(SurfaceFile, AnObjIndexOutOfRangeIsRefused) {
  std::ofstream(file("index.obj")) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n";
  EXPECT_NE(refusal(file("index.obj")).find(":4: face corner '4' refers to no vertex (3 defined"),
            std::string::npos);
  std::ofstream(file("back.obj")) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n";
  EXPECT_NE(refusal(file("back.obj")).find("face corner '-4' refers to no vertex"),
            std::string::npos);
}

TEST_F(SurfaceFile, ATriangleWithoutAreaIsRefused) {
  std::ofstream(file("line.obj")) << "v 0 0 0\nv 1 0 0\nv 3 0 0\nf 1 2 3\n";
  EXPECT_NE(refusal(file("line.obj"))
                .find("triangle 1 with corners (0, 0, 0), (1, 0, 0), (3, 0, 0) has no area"),
            std::string::npos);
}

TEST_F(SurfaceFile, AnOpenOrInconsistentSurfaceIsRefusedAtItsEdge) {
  hs_test::Surface open = kBox;
  open.triangles.pop_back();  // {3, 7, 5}: the x = 1 side loses a triangle
  hs_test::write_stl_binary(file("open.stl"), open);
  EXPECT_NE(refusal(file("open.stl")).find("the edge from"), std::string::npos);
  EXPECT_NE(refusal(file("open.stl")).find("alone: the surface is open there"), std::string::npos);
  hs_test::Surface flipped = kBox;
  std::swap(flipped.triangles[4][1], flipped.triangles[4][2]);
  hs_test::write_obj(file("flipped.obj"), flipped);
  EXPECT_NE(refusal(file("flipped.obj")).find("their orientations disagree"), std::string::npos);
}

TEST_F(SurfaceFile, AnInwardSurfaceIsRefused) {
  hs_test::Surface inward = kBox;
  for (auto& t : inward.triangles) std::swap(t[1], t[2]);
  hs_test::write_obj(file("inward.obj"), inward);
  EXPECT_NE(refusal(file("inward.obj"))
                .find("encloses a volume of -0.125 m^3: its triangles face "
                      "inward"),
            std::string::npos);
}

TEST_F(SurfaceFile, ADeckWithABadSurfaceIsRefusedWhenItIsRead) {
  std::ofstream(file("deck.yaml"))
      << "mesh: {file: " << HYDROSOFT_SOURCE_DIR << "/meshes/block.geo}\n"
      << "materials: [{group: body, model: linear_elastic, E: 1.0e5, nu: 0.3}]\n"
      << "boundary: [{group: bottom}]\n"
      << "obstacles: [{name: cup, type: surface, file: cup.stl}]\n"
      << "contact: {surfaces: [top]}\n";
  try {
    hs::parse_deck(file("deck.yaml"), {});
    ADD_FAILURE() << "accepted";
  } catch (const hs::InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("obstacles[0].file: " + file("cup.stl") + ": cannot read the surface"),
              std::string::npos)
        << what;
  }
  hs_test::write_stl_binary(file("cup.stl"), kBox);  // beside the deck: found
  const hs::Config c = hs::parse_deck(file("deck.yaml"), {});
  ASSERT_EQ(c.obstacles.size(), 1u);
  EXPECT_EQ(c.obstacles[0].surface->num_triangles(), 12u);
}

TEST_F(SurfaceFile, ADeckWithASurfaceRoundTripsThroughItsPrintout) {
  // The printout names the file by its absolute path, so it reads the same surface from
  // anywhere; the fingerprint (a restart's check) by its name, as the mesh's.
  const std::string deck =
      std::string("mesh: {file: ") + HYDROSOFT_SOURCE_DIR + "/meshes/block.geo}\n" +
      "materials: [{group: body, model: linear_elastic, E: 1.0e5, nu: 0.3}]\n"
      "boundary: [{group: bottom}]\n"
      "obstacles: [{name: cup, type: surface, file: cup.obj, scale: 0.5, move: [0, 0, -1]}]\n"
      "contact: {surfaces: [top]}\n";
  fs::create_directory(file("a"));
  fs::create_directory(file("b"));
  for (const char* folder : {"a", "b"}) {
    hs_test::write_obj(file(std::string(folder) + "/cup.obj"), kBox);
    std::ofstream(file(std::string(folder) + "/deck.yaml")) << deck;
  }
  const hs::Config a = hs::parse_deck(file("a/deck.yaml"), {});
  EXPECT_EQ(a.obstacles[0].file, file("a/cup.obj"));
  const std::string printed = hs::format_config(a);
  std::ofstream(file("printed.yaml")) << printed;
  const hs::Config again = hs::parse_deck(file("printed.yaml"), {});
  EXPECT_EQ(again.obstacles[0].file, file("a/cup.obj"));
  EXPECT_EQ(again.obstacles[0].scale, 0.5);
  EXPECT_EQ(again.obstacles[0].surface->vertices()[0], 0.5 * kBox.vertices[0]);
  const std::string reprinted = hs::format_config(again);
  EXPECT_EQ(reprinted.substr(reprinted.find('\n')), printed.substr(printed.find('\n')));
  EXPECT_EQ(hs::config_fingerprint(again), hs::config_fingerprint(a));
  EXPECT_EQ(hs::config_fingerprint(hs::parse_deck(file("b/deck.yaml"), {})),
            hs::config_fingerprint(a));
}

}  // namespace test_contact_surface_file
}  // namespace
