// The closed-form hydrostatic load: total force rho g V and moment rho V x_c x g exactly (the
// divergence theorem for a linear pressure field), rotation-equivariance, and agreement in
// total force and moment with the column method, whose distribution differs.
#include <gtest/gtest.h>

#include <cmath>

#include "support.hpp"

namespace fw = fluidweight;
using namespace fwtest;

namespace {

Vec3 cross(Vec3 a, Vec3 b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

Options hydro(Vec3 gravity) {
  Options o = options(fw::Implementation::cpu_reference, 1, gravity);
  o.method = fw::Method::hydrostatic;
  return o;
}

}  // namespace

TEST(Hydrostatic, TotalForceAndMomentAreExact) {
  std::vector<SurfaceMesh> meshes = {fw::shapes::icosphere(3),
                                     translated(fw::shapes::torus(1, 0.3, 40, 16), {2, 1, -3}),
                                     e_shape(), flipped(comb(4)), fw::shapes::uneven_sphere(3, 8)};
  for (Vec3 g : {Vec3{0, -9.81, 0}, Vec3{1.5, -2.0, 4.0}}) {
    for (size_t m = 0; m < meshes.size(); ++m) {
      Result r = fw::compute(meshes[m], hydro(g));
      double v = std::fabs(volume(meshes[m]));
      Vec3 f = total_force(r), mom = total_moment(meshes[m], r);
      Vec3 expected_m =
          cross(centroid(meshes[m]), {1000 * v * g[0], 1000 * v * g[1], 1000 * v * g[2]});
      double scale = 1000 * v * std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
      for (int d = 0; d < 3; ++d) {
        EXPECT_NEAR(f[d], 1000 * v * g[d], 1e-10 * scale) << "mesh " << m;
        EXPECT_NEAR(mom[d], expected_m[d], 1e-9 * scale * 4) << "mesh " << m;
      }
      EXPECT_NEAR(r.column_volume, v, 1e-12 * v);
    }
  }
}

// Rotating mesh and gravity together rotates every nodal force.
TEST(Hydrostatic, RotatesWithTheScene) {
  SurfaceMesh m = e_shape();
  Mat3 q = rotation({1, 2, 3}, 0.9);
  Result a = fw::compute(m, hydro({0, -9.81, 0}));
  Result b = fw::compute(transformed(m, q), hydro(apply(q, {0, -9.81, 0})));
  Result a_rotated = a;
  for (size_t v = 0; v < a.forces.size(); v += 3) {
    Vec3 f = apply(q, {a.forces[v], a.forces[v + 1], a.forces[v + 2]});
    for (int d = 0; d < 3; ++d) a_rotated.forces[v + d] = f[d];
  }
  EXPECT_LT(force_difference(b, a_rotated), 1e-12);
}

// One node: a cube of side 1 with its floor at depth 1. The floor carries rho g (its area times
// depth), the walls push sideways and cancel, the ceiling carries nothing (depth 0).
TEST(Hydrostatic, FloorWallsAndCeilingOfACube) {
  SurfaceMesh cube = box({1, 1, 1}, 1);
  Result r = fw::compute(cube, hydro({0, -10, 0}));
  double floor = 0, ceiling = 0;
  for (int v = 0; v < cube.num_vertices(); ++v) {
    (cube.vertices[3 * v + 1] == 0 ? floor : ceiling) += r.forces[3 * v + 1];
  }
  EXPECT_NEAR(floor, -1000 * 10, 1e-9);  // pressure rho g 1 on area 1, pushing down
  EXPECT_NEAR(ceiling, 0, 1e-9);
}

// The column method and the closed form agree in total force and moment (the weight acts at
// the centroid) but not node by node: the column method loads floors only, vertically.
TEST(Hydrostatic, AgreesWithColumnMethodInForceAndMoment) {
  SurfaceMesh m = translated(transformed(e_shape(), rotation({1, 0, 1}, 0.25)), {0.3, -2, 1});
  Result h = fw::compute(m, hydro({0, -9.81, 0}));
  Result c = fw::compute(m, options(fw::Implementation::cpu_fast, 600));
  Vec3 fh = total_force(h), fc = total_force(c), mh = total_moment(m, h), mc = total_moment(m, c);
  double w = std::fabs(fh[1]);
  EXPECT_NEAR(fc[1], fh[1], 2e-3 * w);
  for (int d = 0; d < 3; ++d) EXPECT_NEAR(mc[d], mh[d], 5e-3 * w);
  EXPECT_GT(force_difference(c, h), 0.1);  // different distributions
}
