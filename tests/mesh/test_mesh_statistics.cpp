// Mesh statistics against hand computations: a unit cube of six tetrahedra (volume 1/6
// each, a known shape), a regular tetrahedron (quality 1) and its closed surface (enclosing
// its own volume), a flattened one (quality -> 0).
#include <gtest/gtest.h>

#include <cmath>

#include "mesh/mesh_statistics.hpp"

namespace hs {
namespace {

TEST(MeshStatistics, QualityIsOneForARegularTetrahedronAndFallsAsItFlattens) {
  const double a[3] = {1, 1, 1}, b[3] = {1, -1, -1}, c[3] = {-1, 1, -1}, d[3] = {-1, -1, 1};
  EXPECT_NEAR(tet_quality(a, c, b, d), 1.0, 1e-14);
  // d moved to a tenth of its height over the face a, c, b (centroid (1, 1, -1) / 3): volume
  // 8/30, squared edges 3 x 8 + 3 x 2.72, so q = 12 (0.8)^(2/3) / 32.16 = 0.3216.
  const double flat[3] = {0.2, 0.2, -0.2};
  EXPECT_NEAR(tet_quality(a, c, b, flat), 12 * std::cbrt(0.64) / 32.16, 1e-12);
  EXPECT_NEAR(tet_quality(a, b, c, d), -1.0, 1e-14);  // inverted
}

TEST(MeshStatistics, RegularTetrahedronEnclosesItsVolume) {
  Mesh mesh;
  mesh.x = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
  mesh.tets = {0, 2, 1, 3};  // positively oriented
  mesh.tet_volume = {0};
  mesh.volume_names = {"body"};
  // Its four faces, each oriented outward (right-hand normal away from the opposite corner).
  mesh.surfaces["skin"] = {0, 1, 2, 0, 2, 3, 2, 1, 3, 0, 3, 1};
  const auto s = mesh_statistics(mesh, {"skin", "absent"});
  const double volume = 8.0 / 3.0;  // edge 2 sqrt 2: V = a^3 / (6 sqrt 2)
  EXPECT_NEAR(s.smallest_volume, volume, 1e-14);
  EXPECT_NEAR(s.enclosed_volumes.at("skin"), -volume, 1e-14)
      << "faces pointing out of the body: a cavity's convention gives minus the solid's volume";
  EXPECT_EQ(s.enclosed_volumes.count("absent"), 0u);
  EXPECT_EQ(s.lower, (std::array<double, 3>{-1, -1, -1}));
  EXPECT_EQ(s.upper, (std::array<double, 3>{1, 1, 1}));
}

TEST(MeshStatistics, CubeOfSixTetrahedra) {
  Mesh mesh;
  for (int k = 0; k < 8; ++k)
    mesh.x.insert(mesh.x.end(), {double(k & 1), double(k >> 1 & 1), 2.0 * (k >> 2 & 1)});
  // The six tetrahedra around the diagonal 0-7 of a 1 x 1 x 2 box.
  mesh.tets = {0, 1, 3, 7, 0, 3, 2, 7, 0, 2, 6, 7, 0, 6, 4, 7, 0, 4, 5, 7, 0, 5, 1, 7};
  mesh.tet_volume.assign(6, 0);
  mesh.volume_names = {"body"};
  const auto s = mesh_statistics(mesh, {});
  EXPECT_EQ(s.nodes, 8);
  EXPECT_EQ(s.tets, 6);
  EXPECT_NEAR(s.smallest_volume, 2.0 / 6.0, 1e-14);
  EXPECT_EQ(s.upper, (std::array<double, 3>{1, 1, 2}));
  EXPECT_GT(s.worst_quality, 0.0);
  EXPECT_LT(s.worst_quality, 1.0);
  const std::string text = format_statistics(s);
  EXPECT_NE(text.find("nodes 8, tetrahedra 6 (P1), dofs 24"), std::string::npos) << text;
}

}  // namespace
}  // namespace hs
