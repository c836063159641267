// Surface obstacles (src/contact/triangle_surface.cpp): a 12-triangle box gives the analytic
// box's distance, gradient and Hessian; a dented sphere (not convex) its closest point by
// brute force over every triangle and its sign by the winding number, an independent test of
// inside; the gradient and Hessian are central differences of the distance; a tessellated
// sphere's distance approaches the sphere's within the tessellation's sagitta, by a quarter
// each time the edges halve.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "contact/node_contact.hpp"
#include "contact/obstacle.hpp"
#include "contact/triangle_surface.hpp"
#include "surface_test_util.hpp"

namespace {
namespace test_contact_surface {

using V3 = Eigen::Vector3d;

hs::ObstacleShape surface_obstacle(const hs_test::Surface& s, const V3& move = V3::Zero()) {
  hs::ObstacleShape o;
  o.type = hs::ObstacleType::surface;
  o.surface = std::make_shared<const hs::TriangleSurface>(s.vertices, s.triangles);
  o.move = {move(0), move(1), move(2)};
  return o;
}

double segment_distance(const V3& x, const V3& a, const V3& b) {
  const double t = std::clamp((x - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
  return (a + t * (b - a) - x).norm();
}

// The distance to a triangle as its plane's where x projects inside it (by the signs of the
// three sub-triangles' areas), else the nearest of its sides: no Voronoi regions.
double triangle_distance(const V3& x, const V3& a, const V3& b, const V3& c) {
  const V3 n = (b - a).cross(c - a).normalized();
  const V3 p = x - n.dot(x - a) * n;
  const bool inside = (b - a).cross(p - a).dot(n) >= 0 && (c - b).cross(p - b).dot(n) >= 0 &&
                      (a - c).cross(p - c).dot(n) >= 0;
  if (inside) return std::abs(n.dot(x - a));
  return std::min(
      {segment_distance(x, a, b), segment_distance(x, b, c), segment_distance(x, c, a)});
}

// The generalised winding number: the triangles' solid angles at x over 4 pi; 1 inside a
// closed outward surface, 0 outside.
double winding_number(const hs_test::Surface& s, const V3& x) {
  double total = 0;
  for (const auto& f : s.triangles) {
    const V3 a = s.vertices[f[0]] - x, b = s.vertices[f[1]] - x, c = s.vertices[f[2]] - x;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    total += 2 * std::atan2(a.dot(b.cross(c)),
                            la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb);
  }
  return total / (4 * M_PI);
}

void expect_derivatives(const hs::ObstacleShape& o, const V3& x, double tol_hessian) {
  const double h = 1e-7;
  const hs::SignedDistance sd = hs::signed_distance(o, x, 0.5);
  for (int i = 0; i < 3; ++i) {
    V3 xp = x, xm = x;
    xp(i) += h;
    xm(i) -= h;
    const auto p = hs::signed_distance(o, xp, 0.5), m = hs::signed_distance(o, xm, 0.5);
    EXPECT_NEAR(sd.gradient(i), (p.d - m.d) / (2 * h), 1e-7) << x.transpose();
    for (int j = 0; j < 3; ++j)
      EXPECT_NEAR(sd.hessian(j, i), (p.gradient(j) - m.gradient(j)) / (2 * h), tol_hessian)
          << x.transpose();
  }
}

TEST(SurfaceDistance, ABoxOfTwelveTrianglesIsTheAnalyticBox) {
  const V3 center(0.1, -0.2, 0.3), size(1.0, 0.6, 0.4), move(0.1, 0.2, -0.1);
  const hs::ObstacleShape mesh = surface_obstacle(hs_test::box_surface(center, size), move);
  hs::ObstacleShape box;
  box.type = hs::ObstacleType::box;
  box.center = {center(0), center(1), center(2)};
  box.size = {size(0), size(1), size(2)};
  box.move = mesh.move;
  std::mt19937 random(7);
  std::uniform_real_distribution<double> in(-1.2, 1.2);
  int regions[3] = {0, 0, 0};  // points beyond 1, 2, 3 of the box's slabs: face, edge, corner
  for (int k = 0; k < 2000; ++k) {
    const V3 x = center + 0.5 * move + V3(in(random), in(random), in(random)).cwiseProduct(size);
    const auto a = hs::signed_distance(box, x, 0.5), b = hs::signed_distance(mesh, x, 0.5);
    EXPECT_NEAR(b.d, a.d, 1e-14) << x.transpose();
    EXPECT_LT((b.gradient - a.gradient).norm(), 1e-13) << x.transpose();
    EXPECT_LT((b.hessian - a.hessian).norm(), 1e-12 * (1 + a.hessian.norm())) << x.transpose();
    const V3 q = (x - center - 0.5 * move).cwiseAbs() - 0.5 * size;
    const int beyond = (q.array() > 0).count();
    if (beyond > 0) ++regions[beyond - 1];
  }
  EXPECT_GT(regions[0], 100);
  EXPECT_GT(regions[1], 100);
  EXPECT_GT(regions[2], 100);
  // On the diagonal of a side, where two triangles meet flat: the plane's distance, no curve.
  const V3 over = center + 0.5 * move + V3(0.1 * size(0), -0.1 * size(1), 0.5 * size(2) + 0.05);
  EXPECT_EQ(hs::signed_distance(mesh, over, 0.5).hessian, Eigen::Matrix3d::Zero());
  // Turned about its centre (the surface's pivot, the box's own), fixed and with the load.
  hs::ObstacleShape turned_mesh = mesh, turned_box = box;
  turned_mesh.pivot = {center(0), center(1), center(2)};
  for (auto* o : {&turned_mesh, &turned_box}) {
    o->rotation = {20, -35, 50};
    o->turn = {0, 30, 10};
  }
  for (int k = 0; k < 500; ++k) {
    const V3 x = center + 0.5 * move + 1.5 * V3(in(random), in(random), in(random));
    const auto a = hs::signed_distance(turned_box, x, 0.5),
               b = hs::signed_distance(turned_mesh, x, 0.5);
    EXPECT_NEAR(b.d, a.d, 1e-13) << x.transpose();
    EXPECT_LT((b.gradient - a.gradient).norm(), 1e-12) << x.transpose();
    EXPECT_LT((b.hessian - a.hessian).norm(), 1e-11 * (1 + a.hessian.norm())) << x.transpose();
  }
}

// An icosphere with one vertex pushed in to a third of the radius: a dent, not convex.
hs_test::Surface dented_sphere() {
  hs_test::Surface s = hs_test::icosphere(2, 1.0);
  s.vertices[0] *= 0.3;
  return s;
}

TEST(SurfaceDistance, ADentedSphereHasItsClosestPointAndItsWindingSign) {
  const hs_test::Surface s = dented_sphere();
  const hs::ObstacleShape o = surface_obstacle(s);
  std::mt19937 random(11);
  std::uniform_real_distribution<double> in(-1.3, 1.3);
  int inside = 0;
  // Around the dent's rim, whose vertices are saddles (a concave edge down into the dent,
  // convex ones along the rim): there one face's normal alone gives the wrong sign.
  std::vector<int> rim;
  for (const auto& f : s.triangles)
    for (int k = 0; k < 3; ++k)
      if (f[k] == 0) rim.push_back(f[(k + 1) % 3]);
  for (int k = 0; k < 600; ++k) {
    V3 x(in(random), in(random), in(random));
    if (k % 3 == 0) x = s.vertices[0] + 0.4 * V3(in(random), in(random), in(random));
    if (k % 3 == 1)
      x = s.vertices[rim[k % rim.size()]] + 0.05 * V3(in(random), in(random), in(random));
    double reference = 1e300;
    for (const auto& f : s.triangles)
      reference = std::min(
          reference, triangle_distance(x, s.vertices[f[0]], s.vertices[f[1]], s.vertices[f[2]]));
    const double d = hs::signed_distance(o, x, 0).d, w = winding_number(s, x);
    EXPECT_NEAR(std::abs(d), reference, 1e-12) << x.transpose();
    EXPECT_EQ(d<0, w> 0.5) << x.transpose() << " winding " << w;
    inside += d < 0;
  }
  EXPECT_GT(inside, 60);
  EXPECT_LT(inside, 540);
}

TEST(SurfaceDistance, TheStepBoundKeepsANodeOutOfTheDent) {
  // Nodes in the dent's mouth, stepped in random directions as far as across the dent: along
  // the bounded step no point is inside, and it ends at least a tenth of the gap away. The
  // tangent bound of the convex shapes would have put some of them inside.
  const hs_test::Surface s = dented_sphere();
  const hs::ObstacleShape o = surface_obstacle(s, V3(0.1, 0, 0));
  const V3 shift(0.05, 0, 0), mouth = shift + 0.8 * s.vertices[0] / 0.3;
  std::mt19937 random(5);
  std::uniform_real_distribution<double> in(-1, 1);
  int tangent_inside = 0, checked = 0;
  for (int k = 0; k < 400; ++k) {
    const V3 x = mouth + 0.15 * V3(in(random), in(random), in(random));
    const hs::SignedDistance start = hs::signed_distance(o, x, 0.5);
    if (!(start.d > 0)) continue;
    const V3 step = 0.8 * V3(in(random), in(random), in(random));
    const double t = hs::step_bound(o, x, step, 0.5);
    for (int i = 1; i <= 50; ++i)
      ASSERT_GT(hs::signed_distance(o, x + t * i / 50.0 * step, 0.5).d, 0) << x.transpose();
    EXPECT_GE(hs::signed_distance(o, x + t * step, 0.5).d, 0.1 * start.d * (1 - 1e-9));
    const double approach = -start.gradient.dot(step);
    const double tangent = approach > 0 ? std::min(1.0, 0.9 * start.d / approach) : 1.0;
    tangent_inside += hs::signed_distance(o, x + tangent * step, 0.5).d < 0;
    ++checked;
  }
  EXPECT_GT(checked, 200);
  EXPECT_GT(tangent_inside, 10);
}

TEST(SurfaceDistance, GradientAndHessianAreItsDerivatives) {
  const hs::ObstacleShape o = surface_obstacle(dented_sphere(), V3(0.02, 0, -0.04));
  const V3 shift(0.01, 0, -0.02);  // move at s = 0.5
  const auto& v = o.surface->vertices();
  const auto& t = o.surface->triangles()[7];
  const V3 face = (v[t[0]] + v[t[1]] + v[t[2]]) / 3, edge = (v[t[0]] + v[t[1]]) / 2;
  for (double scale : {1.1, 0.95}) {  // outside and inside
    expect_derivatives(o, shift + scale * face, 1e-6);
    expect_derivatives(o, shift + scale * edge + V3(1e-3, 2e-3, 0), 1e-5);
    expect_derivatives(o, shift + scale * v[5] + V3(1e-3, 0, 2e-3), 1e-5);
  }
  expect_derivatives(o, shift + v[0] + V3(0.01, 0.02, 0.5), 1e-5);  // above the dent
  expect_derivatives(o, shift + 0.5 * v[0] + V3(0.01, 0.02, 0.03), 1e-5);
}

TEST(SurfaceDistance, ATessellatedSphereConvergesToTheSphereWithinItsSagitta) {
  // The icosphere's vertices lie on the sphere and its faces inside it, so outside it the
  // mesh's distance exceeds the sphere's by at most R - r_in, r_in the nearest face plane.
  const double R = 0.5;
  hs::ObstacleShape sphere;
  sphere.type = hs::ObstacleType::sphere;
  sphere.radius = R;
  std::mt19937 random(3);
  std::normal_distribution<double> normal;
  double previous = 0;
  for (int level = 1; level <= 5; ++level) {
    const hs_test::Surface s = hs_test::icosphere(level, R);
    const hs::ObstacleShape mesh = surface_obstacle(s);
    double r_in = R;
    for (const auto& f : s.triangles) {
      const V3 n = (s.vertices[f[1]] - s.vertices[f[0]])
                       .cross(s.vertices[f[2]] - s.vertices[f[0]])
                       .normalized();
      r_in = std::min(r_in, n.dot(s.vertices[f[0]]));
    }
    double worst = 0;
    for (int k = 0; k < 500; ++k) {
      const V3 x = V3(normal(random), normal(random), normal(random)).normalized() *
                   (R * (1.001 + 0.2 * (k % 10) / 10));
      const double e = hs::signed_distance(mesh, x, 0).d - hs::signed_distance(sphere, x, 0).d;
      EXPECT_GE(e, -1e-15);
      EXPECT_LE(e, R - r_in + 1e-15) << "level " << level;
      worst = std::max(worst, e);
    }
    if (level > 1) EXPECT_LT(worst, 0.35 * previous) << "level " << level;  // h^2: 1/4
    previous = worst;
  }
}

TEST(SurfaceDistance, ANodeOnATessellatedBallGetsTheBarriersForceAlongTheNormal) {
  // The barrier's force on a node over a face points along the face's normal (d's gradient).
  const hs::ObstacleShape o = surface_obstacle(hs_test::icosphere(3, 0.5));
  const auto& v = o.surface->vertices();
  const auto& t = o.surface->triangles()[40];
  const V3 n = (v[t[1]] - v[t[0]]).cross(v[t[2]] - v[t[0]]).normalized();
  const V3 x = (v[t[0]] + v[t[1]] + v[t[2]]) / 3 + 2e-4 * n;
  const hs::ContactBarrier barrier{1e-3, 1e4};
  const hs::NodeContact c = hs::node_contact({o}, x, 0, 1e-4, barrier, false);
  ASSERT_TRUE(c.valid);
  EXPECT_LT(c.gradient.dot(n), 0);
  EXPECT_LT((c.gradient - c.gradient.dot(n) * n).norm(), 1e-12 * c.gradient.norm());
}

}  // namespace test_contact_surface
}  // namespace
