// The cost of a surface obstacle (docs/contact.md, "Surface obstacles"): the tree's build and
// one signed-distance query, against the triangle count, on icospheres of radius 1 refined
// 3 to 7 times (1,280 to 327,680 triangles). Queries at random points within 0.1 of the
// sphere, where contact nodes are. Medians of 7 repetitions.
//   build/bin/bench_surface_distance
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>

#include "../../tests/contact/surface_test_util.hpp"
#include "contact/triangle_surface.hpp"

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int main() {
  std::printf("triangles,build_ms,query_us\n");
  std::mt19937 random(1);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> radius(0.9, 1.1);
  std::vector<Eigen::Vector3d> points(100000);
  for (auto& p : points)
    p = Eigen::Vector3d(normal(random), normal(random), normal(random)).normalized() *
        radius(random);
  for (int level = 3; level <= 7; ++level) {
    const hs_test::Surface s = hs_test::icosphere(level, 1.0);
    std::vector<double> build, query;
    double sum = 0;  // keeps the queries from being optimised away
    for (int r = 0; r < 7; ++r) {
      auto start = std::chrono::steady_clock::now();
      const hs::TriangleSurface surface(s.vertices, s.triangles);
      build.push_back(1e3 * seconds_since(start));
      start = std::chrono::steady_clock::now();
      for (const auto& p : points) sum += surface.distance(p).d;
      query.push_back(1e6 * seconds_since(start) / points.size());
    }
    std::printf("%zu,%.2f,%.3f\n", s.triangles.size(), median(build), median(query));
    if (sum == 12345) std::printf("\n");
  }
}
