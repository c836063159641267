// The pointwise contact physics (src/contact/): each obstacle's signed distance against the
// geometry it describes, its gradient and Hessian against central differences, the barrier's
// derivatives likewise, and a node's energy, force and Hessian against differences of one
// another; the tangent's projection keeps a positive semi-definite Hessian as it is.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "contact/barrier.hpp"
#include "contact/friction.hpp"
#include "contact/node_contact.hpp"
#include "contact/obstacle.hpp"

namespace {

using hs::ObstacleShape;
using hs::ObstacleType;
using V3 = Eigen::Vector3d;

ObstacleShape plane() {
  ObstacleShape o;
  o.type = ObstacleType::plane;
  o.point = {0.1, -0.2, 0.3};
  const double n = std::sqrt(1.0 + 4.0 + 4.0);
  o.normal = {1 / n, -2 / n, 2 / n};
  o.move = {0.01, 0.02, -0.03};
  return o;
}
ObstacleShape sphere() {
  ObstacleShape o;
  o.type = ObstacleType::sphere;
  o.center = {0.2, 0.1, -0.1};
  o.radius = 0.5;
  o.move = {0, 0, 0.05};
  return o;
}
ObstacleShape cylinder() {
  ObstacleShape o;
  o.type = ObstacleType::cylinder;
  o.center = {0, 0, 0};
  o.radius = 0.3;
  o.axis = {0, 0.6, 0.8};
  return o;
}
ObstacleShape box() {
  ObstacleShape o;
  o.type = ObstacleType::box;
  o.center = {0, 0, 0};
  o.size = {1.0, 0.6, 0.4};
  o.move = {0.1, 0, 0};
  return o;
}

// Central differences of d and of its gradient at x; compared with the analytic ones.
void expect_derivatives(const ObstacleShape& o, const V3& x, double s) {
  const double h = 1e-6;
  const hs::SignedDistance sd = hs::signed_distance(o, x, s);
  for (int i = 0; i < 3; ++i) {
    V3 xp = x, xm = x;
    xp(i) += h;
    xm(i) -= h;
    const auto p = hs::signed_distance(o, xp, s), m = hs::signed_distance(o, xm, s);
    EXPECT_NEAR(sd.gradient(i), (p.d - m.d) / (2 * h), 1e-8) << "type " << int(o.type);
    for (int j = 0; j < 3; ++j)
      EXPECT_NEAR(sd.hessian(j, i), (p.gradient(j) - m.gradient(j)) / (2 * h), 1e-6)
          << "type " << int(o.type);
  }
}

TEST(ObstacleDistance, MatchesItsGeometry) {
  // Plane: the distance along the unit normal from the moved point.
  const ObstacleShape p = plane();
  const V3 x(0.4, 0.5, 0.9), q = V3(0.1, -0.2, 0.3) + 0.5 * V3(0.01, 0.02, -0.03);
  EXPECT_NEAR(hs::signed_distance(p, x, 0.5).d, V3(p.normal.data()).dot(x - q), 1e-15);
  // Sphere: |x - c| - r, the centre moved.
  const ObstacleShape s = sphere();
  EXPECT_NEAR(hs::signed_distance(s, V3(0.2, 0.1, 1.0), 1.0).d, 1.0 - (-0.1 + 0.05) - 0.5, 1e-15);
  // Cylinder: the distance from the axis less the radius, whatever the position along it.
  const ObstacleShape c = cylinder();
  const V3 radial(1, 0, 0), along(0, 0.6, 0.8);
  EXPECT_NEAR(hs::signed_distance(c, 0.7 * radial + 3.0 * along, 0).d, 0.4, 1e-14);
  // Box: to a face, to an edge, to a corner, and inside (to the nearest face).
  const ObstacleShape b = box();
  EXPECT_NEAR(hs::signed_distance(b, V3(0.1, 0, 0.5), 1).d, 0.3, 1e-15);
  EXPECT_NEAR(hs::signed_distance(b, V3(0.1 + 0.8, 0, 0.5), 1).d, std::hypot(0.3, 0.3), 1e-15);
  EXPECT_NEAR(hs::signed_distance(b, V3(0.1 + 0.6, 0.4, 0.3), 1).d, std::sqrt(0.01 + 0.01 + 0.01),
              1e-15);
  EXPECT_NEAR(hs::signed_distance(b, V3(0.1, 0.25, 0), 1).d, -0.05, 1e-15);
}

TEST(ObstacleDistance, GradientAndHessianAreItsDerivatives) {
  expect_derivatives(plane(), V3(0.4, 0.5, 0.9), 0.7);
  expect_derivatives(sphere(), V3(0.5, -0.3, 0.8), 0.3);
  expect_derivatives(cylinder(), V3(0.5, -0.3, 0.8), 0);
  expect_derivatives(box(), V3(0.2, 0.1, 0.6), 1);    // over a face
  expect_derivatives(box(), V3(0.9, 0.05, 0.5), 1);   // beside an edge
  expect_derivatives(box(), V3(0.9, 0.45, 0.35), 1);  // beyond a corner
  expect_derivatives(box(), V3(0.15, 0.05, 0.1), 1);  // inside
}

// A rotation is a change of frame: a box turned 90 degrees about z is the box with its x and
// y edges swapped; a turn of 180 degrees at half load is a rotation of 90; a plane turned 90
// degrees about x has its normal turned to -y; gradients and Hessians stay the derivatives.
TEST(ObstacleDistance, RotatedShapesAreTheShapesInTurnedFrames) {
  ObstacleShape turned = box(), swapped = box();
  turned.rotation = {0, 0, 90};
  swapped.size = {0.6, 1.0, 0.4};
  ObstacleShape half = box();
  half.turn = {0, 0, 180};
  half.move = {0.2, 0, 0};  // at half load where the others are at full load
  const V3 points[] = {V3(0.2, 0.1, 0.6), V3(0.9, 0.05, 0.5), V3(0.5, 0.7, 0.35),
                       V3(0.15, 0.05, 0.1), V3(-0.6, -0.4, 0.3)};
  for (const V3& x : points) {
    const auto a = hs::signed_distance(turned, x, 1), b = hs::signed_distance(swapped, x, 1),
               c = hs::signed_distance(half, x, 0.5);
    EXPECT_NEAR(a.d, b.d, 1e-14) << x.transpose();
    EXPECT_NEAR(c.d, b.d, 1e-14) << x.transpose();
    EXPECT_LT((a.gradient - b.gradient).norm(), 1e-14) << x.transpose();
    EXPECT_LT((a.hessian - b.hessian).norm(), 1e-12 * (1 + b.hessian.norm())) << x.transpose();
  }
  ObstacleShape floor;
  floor.type = ObstacleType::plane;
  floor.point = {0, 0, 0.1};
  floor.rotation = {90, 0, 0};
  const auto d = hs::signed_distance(floor, V3(0.3, -0.5, 0.1), 0);
  EXPECT_NEAR(d.d, 0.5, 1e-15);
  EXPECT_LT((d.gradient - V3(0, -1, 0)).norm(), 1e-15);
  // Turned while it moves: a cylinder and a box at a load factor between 0 and 1.
  ObstacleShape c = cylinder(), b = box();
  c.rotation = {10, -20, 5};
  c.turn = {0, 40, 0};
  c.move = {0.1, 0, 0};
  b.rotation = {0, 30, 0};
  b.turn = {15, 0, 45};
  expect_derivatives(c, V3(0.5, -0.3, 0.8), 0.6);
  expect_derivatives(b, V3(0.9, 0.05, 0.5), 0.4);
  expect_derivatives(b, V3(0.9, 0.45, 0.35), 0.8);
}

TEST(ContactBarrier, DerivativesAndLimits) {
  const double dhat = 2e-3, h = 1e-9;
  for (double d : {1e-5, 3e-4, 1e-3, 1.9e-3}) {
    const auto b = hs::contact_barrier(d, dhat);
    const auto p = hs::contact_barrier(d + h, dhat), m = hs::contact_barrier(d - h, dhat);
    EXPECT_NEAR(b.slope, (p.value - m.value) / (2 * h), 1e-6 * std::abs(b.slope) + 1e-12);
    EXPECT_NEAR(b.curvature, (p.slope - m.slope) / (2 * h), 1e-6 * std::abs(b.curvature));
    EXPECT_GT(b.value, 0);
    EXPECT_LT(b.slope, 0);  // it pushes the node away
  }
  // C2 where contact opens: value, slope and curvature vanish at dhat.
  const auto edge = hs::contact_barrier(dhat * (1 - 1e-9), dhat);
  EXPECT_LT(edge.value, 1e-20);
  EXPECT_LT(std::abs(edge.slope), 1e-14);
  EXPECT_LT(std::abs(edge.curvature), 1e-7);
  EXPECT_EQ(hs::contact_barrier(dhat, dhat).value, 0);
  // Near the obstacle the pressure grows as dhat^2 / d.
  const double d = 1e-9;
  EXPECT_NEAR(-hs::contact_barrier(d, dhat).slope * d / (dhat * dhat), 1.0, 1e-4);
}

TEST(NodeContact, ForceAndHessianAreTheEnergysDerivatives) {
  const double area = 1.7e-3, s = 0.4, h = 1e-7;
  // At gap 0.1 from the sphere, 0.26 from the box's face, 0.15 from a plane through it.
  const V3 x = V3(0.2, 0.1, -0.1 + 0.4 * 0.05) + V3(0.6, 0, 0);
  ObstacleShape tilted = plane();
  const V3 n(tilted.normal.data());
  for (int i = 0; i < 3; ++i) tilted.point[i] = x(i) - 0.15 * n(i) - s * tilted.move[i];
  const std::vector<ObstacleShape> obstacles = {tilted, sphere(), box()};
  const hs::ContactBarrier barrier{0.3, 3e4};
  const hs::NodeContact c = hs::node_contact(obstacles, x, s, area, barrier, false);
  ASSERT_TRUE(c.valid);
  int active = 0;
  for (char a : c.active) active += a;
  ASSERT_EQ(active, 3);
  for (int i = 0; i < 3; ++i) {
    V3 xp = x, xm = x;
    xp(i) += h;
    xm(i) -= h;
    const auto p = hs::node_contact(obstacles, xp, s, area, barrier, false);
    const auto m = hs::node_contact(obstacles, xm, s, area, barrier, false);
    EXPECT_NEAR(c.gradient(i), (p.energy - m.energy) / (2 * h), 1e-6 * c.gradient.norm());
    for (int j = 0; j < 3; ++j)
      EXPECT_NEAR(c.hessian(j, i), (p.gradient(j) - m.gradient(j)) / (2 * h),
                  1e-5 * c.hessian.norm());
    // Each obstacle's stiffness is the derivative of the force on that obstacle alone (a
    // contact-force effector's row).
    for (size_t o = 0; o < obstacles.size(); ++o)
      for (int j = 0; j < 3; ++j)
        EXPECT_NEAR(c.stiffness[o](j, i), (p.force[o](j) - m.force[o](j)) / (2 * h),
                    1e-5 * c.stiffness[o].norm())
            << "obstacle " << o;
  }
  // The per-obstacle forces sum to the gradient, their stiffnesses to the Hessian.
  V3 sum = V3::Zero();
  Eigen::Matrix3d stiffness = Eigen::Matrix3d::Zero();
  for (size_t o = 0; o < obstacles.size(); ++o) {
    sum += c.force[o];
    stiffness += c.stiffness[o];
  }
  EXPECT_LT((sum - c.gradient).norm(), 1e-14 * c.gradient.norm());
  EXPECT_LT((stiffness - c.hessian).norm(), 1e-14 * c.hessian.norm());
}

TEST(NodeContact, ProjectionKeepsADefiniteHessianAndClampsAnIndefiniteOne) {
  const hs::ContactBarrier barrier{0.1, 1e3};
  // Against a plane alone the Hessian is kappa A b'' n n^T: semi-definite, kept as it is.
  const std::vector<ObstacleShape> flat = {plane()};
  const V3 near_plane = V3(0.1, -0.2, 0.3) + 0.05 * V3(flat[0].normal.data());
  const auto exact = hs::node_contact(flat, near_plane, 0, 1.0, barrier, false);
  const auto projected = hs::node_contact(flat, near_plane, 0, 1.0, barrier, true);
  EXPECT_LT((exact.hessian - projected.hessian).norm(), 1e-12 * exact.hessian.norm());
  // Close to a small sphere the tangential part b'/r is negative: clamped to zero.
  ObstacleShape ball = sphere();
  ball.radius = 0.01;
  ball.move = {0, 0, 0};
  const V3 x = V3(0.2, 0.1, -0.1) + V3(0.01 + 0.09, 0, 0);
  const auto e = hs::node_contact({ball}, x, 0, 1.0, barrier, false);
  const auto p = hs::node_contact({ball}, x, 0, 1.0, barrier, true);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> exact_eig(e.hessian), projected_eig(p.hessian);
  EXPECT_LT(exact_eig.eigenvalues().minCoeff(), 0);
  EXPECT_GE(projected_eig.eigenvalues().minCoeff(), -1e-12 * p.hessian.norm());
  // The normal stiffness b'' stays.
  EXPECT_NEAR(p.hessian(0, 0), e.hessian(0, 0), 1e-10 * e.hessian.norm());
}

TEST(NodeContact, ANodeInsideAnObstacleIsRefused) {
  const hs::ContactBarrier barrier{0.1, 1e3};
  // Inside the sphere, 0.15 above the box.
  const auto c = hs::node_contact({box(), sphere()}, V3(0.2, 0.1, 0.35), 0, 1.0, barrier, false);
  EXPECT_FALSE(c.valid);
  EXPECT_EQ(c.inside, 1);
}

// A node on a plane with friction 0.4, lagged at x0 with its anchor there: the friction's
// force and Hessian are its energy's derivatives, sticking (slip below eps_v) and sliding;
// sliding, the force is mu lambda against the slip; the anchor of a sliding node follows it to
// eps_v behind, a sticking node's stays.
TEST(Friction, ForceAndHessianAreTheEnergysDerivativesStickingAndSliding) {
  ObstacleShape floor;
  floor.type = ObstacleType::plane;
  floor.friction = 0.4;
  floor.move = {0.01, -0.02, 0};
  const hs::ContactBarrier barrier{1e-3, 1e6};
  const double area = 2e-4, eps = 1e-5, s0 = 0.2, s = 0.3;
  const V3 x0(0.01, 0.02, 4e-4);
  const hs::FrictionLag lag = hs::friction_lag({floor}, x0, s0, area, barrier, eps, {});
  const double lambda = -1e6 * area * hs::contact_barrier(4e-4, 1e-3).slope;
  ASSERT_NEAR(lag.normal_force[0], lambda, 1e-12 * lambda);
  for (double slip : {3e-6, 4e-5}) {
    // The node moved with the floor (s - s0) move, then slipped along (3, 4, 0) / 5.
    const V3 move(0.01, -0.02, 0), dir(0.6, 0.8, 0);
    const V3 x = x0 + (s - s0) * move + slip * dir + V3(0, 0, 1e-5);
    auto at = [&](const V3& y) {
      hs::NodeContact c;
      c.force.assign(1, V3::Zero());
      c.stiffness.assign(1, Eigen::Matrix3d::Zero());
      hs::add_friction({floor}, lag, y, s, eps, c);
      return c;
    };
    const hs::NodeContact c = at(x);
    const double h = 1e-9;
    for (int i = 0; i < 3; ++i) {
      V3 xp = x, xm = x;
      xp(i) += h;
      xm(i) -= h;
      const auto p = at(xp), m = at(xm);
      EXPECT_NEAR(c.gradient(i), (p.energy - m.energy) / (2 * h), 1e-5 * c.gradient.norm());
      for (int j = 0; j < 3; ++j)
        EXPECT_NEAR(c.hessian(j, i), (p.gradient(j) - m.gradient(j)) / (2 * h),
                    1e-5 * c.hessian.norm());
    }
    // One obstacle: its force and stiffness are the whole gradient and Hessian.
    EXPECT_EQ(c.force[0], c.gradient);
    EXPECT_EQ(c.stiffness[0], c.hessian);
    EXPECT_NEAR(c.gradient.dot(V3(0, 0, 1)), 0, 1e-14);  // tangential
    if (slip > eps) {
      EXPECT_NEAR(c.gradient.norm(), 0.4 * lambda, 1e-12 * lambda);
      EXPECT_NEAR(c.gradient.normalized().dot(dir), 1, 1e-12);
    } else {
      EXPECT_LT(c.gradient.norm(), 0.4 * lambda);
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(c.hessian);
    EXPECT_GE(eig.eigenvalues().minCoeff(), -1e-9 * c.hessian.norm());
    // The next step's anchor: eps behind a sliding node, where it was for a sticking one.
    const hs::FrictionLag next = hs::friction_lag({floor}, x, s, area, barrier, eps, lag);
    const V3 here = x - s * move;
    const V3 behind = here - next.anchor[0];
    if (slip > eps) {
      EXPECT_NEAR(V3(behind(0), behind(1), 0).norm(), eps, 1e-15);
    } else {
      EXPECT_NEAR((next.anchor[0] - lag.anchor[0]).head<2>().norm(), 0, 1e-15);
    }
  }
}

}  // namespace
