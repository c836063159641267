// column_head's CPU fast path (closed-form sums over each triangle's covered rows) gives the
// reference's columns, volumes and nodal forces, and the liquid's weight as its net force.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "support.hpp"

namespace fw = fluidweight;
using namespace fwtest;

namespace {

Options head_options(fw::Implementation implementation, int n, Vec3 gravity) {
  Options o = options(implementation, n, gravity);
  o.method = fw::Method::column_head;
  return o;
}

// Volumes agree to 1e-12 of the cavity's; at the finest grids summing a million sections
// rounds differently in each implementation (the plain fast path's tests allow 1e-11 there).
void expect_same(const SurfaceMesh& mesh, int n, Vec3 gravity = {0, -9.81, 0},
                 double volume_tolerance = 1e-12) {
  SCOPED_TRACE("grid " + std::to_string(n));
  const Result ref = fw::compute(mesh, head_options(fw::Implementation::cpu_reference, n, gravity));
  const Result fast = fw::compute(mesh, head_options(fw::Implementation::cpu_fast, n, gravity));
  const double volume = std::fabs(ref.signed_volume);
  EXPECT_NEAR(fast.column_volume, ref.column_volume, volume_tolerance * volume);
  EXPECT_EQ(ref.unmatched_columns, 0);
  EXPECT_EQ(fast.unmatched_columns, 0);
  EXPECT_LT(force_difference(fast, ref), 1e-11);
  // The same columns as the paper's method: the same column volume.
  Options plain = options(fw::Implementation::cpu_fast, n, gravity);
  EXPECT_NEAR(fast.column_volume, fw::compute(mesh, plain).column_volume,
              volume_tolerance * volume);
  // The head's floor and ceiling loads cancel to the weight: rho |g| V_columns along gravity.
  const Vec3 f = total_force(fast);
  const double g =
      std::sqrt(gravity[0] * gravity[0] + gravity[1] * gravity[1] + gravity[2] * gravity[2]);
  for (int d = 0; d < 3; ++d)
    EXPECT_NEAR(f[d], 1000.0 * gravity[d] * fast.column_volume, 1e-10 * 1000.0 * g * volume);
}

}  // namespace

TEST(ColumnHeadFast, MatchesReferenceOnVariedShapes) {
  std::vector<SurfaceMesh> meshes = {
      fw::shapes::icosphere(4),
      transformed(fw::shapes::torus(1, 0.3, 48, 20), rotation({1, 0.2, 0}, 1.2)),
      e_shape(),
      comb(9),
      fw::shapes::uneven_sphere(3, 10.0),
      octahedron({0, 0, 0}, 1.0),
      shuffled(comb(4), 7)};
  for (size_t m = 0; m < meshes.size(); ++m) {
    SCOPED_TRACE("mesh " + std::to_string(m));
    for (int n : {1, 15, 31, 64, 255}) expect_same(meshes[m], n);
  }
}

TEST(ColumnHeadFast, InwardOrientationOtherGravityAndFineGrids) {
  expect_same(flipped(transformed(e_shape(), rotation({0.3, 1, 0.1}, 0.7))), 90, {1.0, 2.0, -3.0});
  expect_same(fw::shapes::torus(1, 0.4, 40, 16), 77, {0, 0, -9.81});
  const SurfaceMesh tilted =
      translated(transformed(e_shape(), rotation({1, 0, 1}, 0.25)), {0.3, -2, 1});
  for (int n : {300, 1000}) expect_same(tilted, n, {0, -9.81, 0}, 1e-11);
}

// A context computes again with new positions, as a control loop does.
TEST(ColumnHeadFast, ContextFollowsMovingVertices) {
  SurfaceMesh a = fw::shapes::icosphere(3);
  SurfaceMesh b = transformed(a, rotation({1, 1, 1}, 0.5));
  for (size_t v = 0; v < b.vertices.size(); ++v) b.vertices[v] *= 1.0 + 0.1 * (v % 3);
  const Options fast = head_options(fw::Implementation::cpu_fast, 120, {0, -9.81, 0});
  const Options ref = head_options(fw::Implementation::cpu_reference, 120, {0, -9.81, 0});
  fw::Context context(fast);
  context.set_cavities({a});
  const Result first = context.compute().front();
  context.set_positions({b.vertices.data()});
  const Result second = context.compute().front();
  EXPECT_LT(force_difference(first, fw::compute(a, ref)), 1e-11);
  EXPECT_LT(force_difference(second, fw::compute(b, ref)), 1e-11);
  EXPECT_NEAR(second.column_volume, fw::compute(b, ref).column_volume, 1e-12);
}
