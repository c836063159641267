// The training designs of `hydrosoft reduce` (reduction/design.hpp): the grid's points,
// serpentine walk and held-back midpoints; the Halton design's corners, its stratification
// (the van der Corput property of its base-2 coordinate) and its nearest-neighbour walk.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "reduction/design.hpp"

namespace {

double distance(const std::vector<double>& a, const std::vector<double>& b) {
  double d2 = 0;
  for (size_t i = 0; i < a.size(); ++i) d2 += (a[i] - b[i]) * (a[i] - b[i]);
  return std::sqrt(d2);
}

TEST(GridDesign, EveryPointOnceEachANeighbourOfTheLastAndTheOddMidpointsHeldBack) {
  const hs::TrainingDesign g = hs::grid_design(2, 5);
  ASSERT_EQ(g.points.size(), 25u);
  std::set<std::vector<double>> distinct(g.points.begin(), g.points.end());
  EXPECT_EQ(distinct.size(), 25u);
  for (size_t i = 1; i < g.points.size(); ++i)
    EXPECT_NEAR(distance(g.points[i], g.points[i - 1]), 0.25, 1e-15) << i;
  int held = 0;
  for (size_t i = 0; i < g.points.size(); ++i) {
    const bool odd =
        std::lround(4 * g.points[i][0]) % 2 == 1 && std::lround(4 * g.points[i][1]) % 2 == 1;
    EXPECT_EQ(g.held_back[i], odd) << i;
    held += g.held_back[i];
  }
  EXPECT_EQ(held, 4);
}

TEST(HaltonDesign, CornersStratifiedPointsAQuarterHeldBackAndANearestNeighbourWalk) {
  const int m = 3, n = 8 + 64;
  const std::vector<double> start = {0.3, 0.3, 0.3};
  const hs::TrainingDesign h = hs::halton_design(m, n, start);
  ASSERT_EQ(h.points.size(), static_cast<size_t>(n));
  std::set<std::vector<double>> distinct(h.points.begin(), h.points.end());
  EXPECT_EQ(distinct.size(), static_cast<size_t>(n));
  for (int c = 0; c < 8; ++c)
    EXPECT_TRUE(distinct.count({double(c & 1), double((c >> 1) & 1), double((c >> 2) & 1)})) << c;
  // The 64 Halton points' first coordinate (base 2) with the origin: one in each 1/64.
  std::set<long> cells = {0};
  for (const auto& x : h.points) {
    for (double v : x) EXPECT_TRUE(v >= 0 && v <= 1);
    const bool corner = std::all_of(x.begin(), x.end(), [](double v) { return v == 0 || v == 1; });
    if (!corner) cells.insert(static_cast<long>(std::floor(64 * x[0])));
  }
  EXPECT_EQ(cells.size(), 64u);
  EXPECT_EQ(std::count(h.held_back.begin(), h.held_back.end(), true), 16);
  // The walk: the first point is the one nearest the start, each next the nearest unvisited.
  for (const auto& x : h.points) EXPECT_LE(distance(h.points[0], start), distance(x, start));
  for (size_t i = 1; i < h.points.size(); ++i)
    for (size_t j = i; j < h.points.size(); ++j)
      EXPECT_LE(distance(h.points[i], h.points[i - 1]), distance(h.points[j], h.points[i - 1]));
  EXPECT_THROW(hs::halton_design(3, 11, start), std::invalid_argument);  // fewer than 2^3 + 4
}

}  // namespace
