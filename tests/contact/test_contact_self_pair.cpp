// Self-contact's node-triangle pairs (contact/surface_pair.hpp): the nearest feature against
// the distance by brute force over the triangle, and the pair's barrier gradient and Hessian
// against central differences of its energy and gradient, for a face, an edge and a vertex;
// the same for the edge-edge pairs, with their mollifier;
// the same for the pair's lagged friction, whose forces balance.
#include <gtest/gtest.h>

#include <random>

#include "contact/box_tree.hpp"
#include "contact/pair_friction.hpp"
#include "contact/surface_pair.hpp"

namespace {

using Eigen::Vector3d;

double feature_distance(const Vector3d& p, const Vector3d* t) {
  const hs::TriangleFeature f = hs::nearest_feature(p, t[0], t[1], t[2]);
  Vector3d y[4] = {p};
  for (int k = 0; k < f.count; ++k) y[1 + k] = t[f.vertex[k]];
  return std::sqrt(hs::feature_squared_distance(y, f.count + 1));
}

// The smallest distance from p to points of the triangle on a fine barycentric grid, and a
// bound of its error (half the grid's spacing along the longest edge).
double brute_distance(const Vector3d& p, const Vector3d* t, int n) {
  double best = 1e300;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j) {
      const double a = double(i) / n, b = double(j) / n;
      best = std::min(best, (p - ((1 - a - b) * t[0] + a * t[1] + b * t[2])).norm());
    }
  return best;
}

TEST(SelfContactPair, TheNearestFeatureGivesTheTrianglesDistance) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> u(-1, 1);
  const Vector3d t[3] = {{0, 0, 0}, {1, 0, 0.2}, {0.3, 0.9, -0.1}};
  const int n = 600;
  int kinds[4] = {0, 0, 0, 0};
  for (int k = 0; k < 300; ++k) {
    const Vector3d p(1.5 * u(random) + 0.4, 1.5 * u(random) + 0.3, 0.6 * u(random));
    const double d = feature_distance(p, t), brute = brute_distance(p, t, n);
    EXPECT_LE(d, brute + 1e-12) << k;  // a feature's distance is a distance to the triangle
    EXPECT_GE(d, brute - 1.5 / n) << k;
    ++kinds[hs::nearest_feature(p, t[0], t[1], t[2]).count];
  }
  EXPECT_GT(kinds[1], 10);  // vertices, edges and the face all met
  EXPECT_GT(kinds[2], 10);
  EXPECT_GT(kinds[3], 10);
}

// Central differences of the energy and the gradient against the pair's own.
void expect_derivatives(Vector3d* x, int count) {
  const hs::ContactBarrier barrier{0.1, 1e4};
  const double area = 0.3, h = 1e-7;
  const hs::PairTerm term = hs::pair_barrier(x, count, area, barrier, false);
  ASSERT_GT(term.energy, 0);
  for (int k = 0; k < 3 * count; ++k) {
    double& c = x[k / 3](k % 3);
    const double keep = c;
    c = keep + h;
    const hs::PairTerm plus = hs::pair_barrier(x, count, area, barrier, false);
    c = keep - h;
    const hs::PairTerm minus = hs::pair_barrier(x, count, area, barrier, false);
    c = keep;
    const double scale = term.gradient.norm();
    EXPECT_NEAR(term.gradient(k), (plus.energy - minus.energy) / (2 * h), 1e-6 * scale) << k;
    const hs::PairVector column = (plus.gradient - minus.gradient) / (2 * h);
    for (int i = 0; i < 3 * count; ++i)
      EXPECT_NEAR(term.hessian(i, k), column(i), 1e-5 * term.hessian.norm()) << i << " " << k;
  }
  // The node and the feature are pushed apart equally (no net force on the pair).
  Vector3d sum = Vector3d::Zero();
  for (int a = 0; a < count; ++a) sum += term.gradient.segment<3>(3 * a);
  EXPECT_LT(sum.norm(), 1e-10 * term.gradient.norm());
}

TEST(SelfContactPair, TheBarriersDerivativesAreTheEnergysForAFaceAnEdgeAndAVertex) {
  Vector3d face[4] = {{0.3, 0.2, 0.02}, {0, 0, 0}, {1, 0.1, 0.05}, {0.2, 0.9, -0.03}};
  expect_derivatives(face, 4);
  Vector3d edge[3] = {{0.5, -0.03, 0.01}, {0, 0, 0}, {1, 0.1, 0.05}};
  expect_derivatives(edge, 3);
  Vector3d vertex[2] = {{0.02, -0.01, 0.015}, {0, 0, 0}};
  expect_derivatives(vertex, 2);
}

// The smallest distance between points of two segments on a fine grid of their parameters.
double brute_edge_distance(const Vector3d* x, int n) {
  double best = 1e300;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double s = double(i) / n, t = double(j) / n;
      best = std::min(best, ((1 - s) * x[0] + s * x[1] - (1 - t) * x[2] - t * x[3]).norm());
    }
  return best;
}

TEST(SelfContactPair, TheNearestEdgeFeaturesGiveTheSegmentsDistance) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> u(-1, 1);
  const int n = 800;
  int kinds[5] = {0, 0, 0, 0, 0};
  for (int k = 0; k < 300; ++k) {
    Vector3d x[4];
    for (Vector3d& v : x) v = Vector3d(u(random), u(random), 0.5 * u(random));
    const hs::EdgeFeature f = hs::nearest_edge_feature(x);
    const double d = std::sqrt(hs::edge_squared_distance(x, f)), brute = brute_edge_distance(x, n);
    EXPECT_LE(d, brute + 1e-12) << k;  // a distance between points of the two segments
    EXPECT_GE(d, brute - 4.0 / n) << k;
    // The feature's weights give its two nearest points, that far apart.
    double w[4];
    hs::edge_feature_weights(x, f, w);
    EXPECT_NEAR((w[0] * x[0] + w[1] * x[1] + w[2] * x[2] + w[3] * x[3]).norm(), d, 1e-12) << k;
    EXPECT_NEAR(w[0] + w[1], 1, 1e-14);
    EXPECT_NEAR(w[2] + w[3], -1, 1e-14);
    ++kinds[f.count];
  }
  EXPECT_GT(kinds[2], 10);  // vertex-vertex, vertex-line and line-line all met
  EXPECT_GT(kinds[3], 10);
  EXPECT_GT(kinds[4], 10);
}

// The edge pair's gradient and Hessian against central differences, for two crossing edges
// (line-line), an edge's end above the other (vertex-line), two ends (vertex-vertex), and
// nearly parallel edges, whose pair the mollifier scales down; the forces on the four nodes
// add up to zero. The mollifier joins its plateau with value and slope: the energy just
// below and just above c = eps agree.
TEST(SelfContactPair, TheEdgePairsDerivativesAreItsEnergysAndItFadesOutAsTheEdgesTurnParallel) {
  const hs::ContactBarrier barrier{0.1, 1e4};
  const double weight = 0.2;
  auto term_of = [&](const Vector3d* x, double parallel) {
    return hs::edge_pair_barrier(x, hs::nearest_edge_feature(x), weight, parallel, barrier, false);
  };
  auto check = [&](Vector3d* x, int count, double parallel) {
    ASSERT_EQ(hs::nearest_edge_feature(x).count, count);
    const hs::PairTerm term = term_of(x, parallel);
    ASSERT_GT(term.energy, 0);
    const double h = 1e-7;
    for (int k = 0; k < 12; ++k) {
      double& c = x[k / 3](k % 3);
      const double keep = c;
      c = keep + h;
      const hs::PairTerm plus = term_of(x, parallel);
      c = keep - h;
      const hs::PairTerm minus = term_of(x, parallel);
      c = keep;
      EXPECT_NEAR(term.gradient(k), (plus.energy - minus.energy) / (2 * h),
                  1e-6 * term.gradient.norm())
          << count << " " << k;
      const hs::PairVector column = (plus.gradient - minus.gradient) / (2 * h);
      for (int i = 0; i < 12; ++i)
        EXPECT_NEAR(term.hessian(i, k), column(i), 1e-5 * term.hessian.norm())
            << count << " " << i << " " << k;
    }
    Vector3d sum = Vector3d::Zero();
    for (int a = 0; a < 4; ++a) sum += term.gradient.segment<3>(3 * a);
    EXPECT_LT(sum.norm(), 1e-10 * term.gradient.norm()) << count;
  };
  Vector3d crossing[4] = {
      {-0.5, 0.02, 0}, {0.6, -0.01, 0.01}, {0.03, -0.4, 0.05}, {-0.02, 0.5, 0.04}};
  check(crossing, 4, 1e-3);
  Vector3d above_end[4] = {{-0.5, 0, 0}, {0.5, 0, 0}, {0.1, 0.03, 0.04}, {0.2, 0.9, 0.5}};
  check(above_end, 3, 1e-3);
  Vector3d ends[4] = {{-0.5, 0, 0}, {0, 0, 0}, {0.03, 0.02, 0.04}, {0.5, 0.3, 0.2}};
  check(ends, 2, 1e-3);
  // |a|^2 |b|^2 = 1 and sin^2 of their angle c = 1e-4, between eps/2 and eps = 1.6e-4.
  Vector3d parallel[4] = {{-0.5, 0, 0}, {0.5, 0, 0}, {-0.5, -0.005, 0.05}, {0.5, 0.005, 0.05}};
  const double c = (parallel[1] - parallel[0]).cross(parallel[3] - parallel[2]).squaredNorm();
  check(parallel, 4, 1.6 * c);
  const double full = term_of(parallel, 0.5 * c).energy;
  EXPECT_NEAR(term_of(parallel, c * (1 + 1e-6)).energy, full, 1e-8 * full);
  // m at c = 0.625 eps: the smoothstep at a quarter, 0.103515625; none at eps/2.
  EXPECT_NEAR(term_of(parallel, 1.6 * c).energy, 0.103515625 * full, 1e-12 * full);
  EXPECT_NEAR(term_of(parallel, 2 * c * (1 - 1e-6)).energy, 0, 1e-15 * full);
}

TEST(SelfContactPair, TheBoxTreeFindsEveryOverlappingBox) {
  std::mt19937 random(3);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Eigen::AlignedBox3d> boxes;
  for (int k = 0; k < 500; ++k) {
    const Vector3d low(u(random), u(random), u(random));
    boxes.emplace_back(low, low + 0.05 * Vector3d(u(random), u(random), u(random)));
  }
  const hs::BoxTree tree(boxes);
  for (int q = 0; q < 50; ++q) {
    const Vector3d low(u(random), u(random), u(random));
    const Eigen::AlignedBox3d box(low, low + 0.1 * Vector3d::Ones());
    std::vector<int> found, expected;
    tree.overlapping(box, [&](int i) { found.push_back(i); });
    for (int i = 0; i < 500; ++i)
      if (boxes[i].intersects(box)) expected.push_back(i);
    std::sort(found.begin(), found.end());
    EXPECT_EQ(found, expected) << q;
  }
}

}  // namespace

// Friction between a node and a triangle's face, edge or vertex (contact/pair_friction.hpp),
// lagged where the node sits above the feature, then the node and the triangle moved apart
// sideways (the triangle also moved as a whole, which costs nothing): the feature's weights
// give back the nearest point; the term's gradient and Hessian are its energy's derivatives;
// the forces on the pair's nodes add up to zero and lie in the lagged tangent plane; sliding,
// the force on the node is mu lambda against the slip; the next lag carries the slip (into
// its turned tangent plane at the same length), eps_v of it where the pair slid.
TEST(SelfContactPair, FrictionsDerivativesAreItsEnergysAndItsForcesBalance) {
  const Vector3d t[3] = {{0, 0, 0}, {1, 0, 0.2}, {0.3, 0.9, -0.1}};
  const Vector3d normal = (t[1] - t[0]).cross(t[2] - t[0]).normalized();
  const double mu = 0.4, lambda = 2.5, eps = 1e-3;
  // Nodes above the face's inside, beyond the edge t0 t1, and beyond the vertex t0.
  const Vector3d above[3] = {(t[0] + t[1] + t[2]) / 3 + 0.05 * normal,
                             0.5 * (t[0] + t[1]) + Vector3d(0, -0.04, 0.02),
                             {-0.03, -0.03, 0.02}};
  const int counts[3] = {4, 3, 2};
  for (int kind = 0; kind < 3; ++kind) {
    const hs::TriangleFeature f = hs::nearest_feature(above[kind], t[0], t[1], t[2]);
    ASSERT_EQ(f.count + 1, counts[kind]);
    Vector3d x[4] = {above[kind]};
    int32_t nodes[4] = {0, 1, 2, 3};
    for (int k = 0; k < f.count; ++k) x[1 + k] = t[f.vertex[k]];
    const int n = f.count + 1;
    double beta[3];
    hs::feature_weights(x, n, beta);
    Vector3d q = Vector3d::Zero();
    for (int k = 1; k < n; ++k) q += beta[k - 1] * x[k];
    const Vector3d to_node = x[0] - q;
    EXPECT_NEAR(std::sqrt(hs::feature_squared_distance(x, n)), to_node.norm(), 1e-14) << kind;
    const hs::PairFrictionLag lag =
        hs::pair_friction_lag(nodes, x, n, 7, mu, lambda, Vector3d::Zero(), eps);
    const Vector3d dir = to_node.unitOrthogonal();  // a tangential slip
    for (double slip : {3e-4, 4e-2}) {
      Vector3d y[4];
      for (int k = 0; k < n; ++k) y[k] = x[k] + Vector3d(0.01, -0.02, 0.03);
      y[0] += slip * dir;
      const hs::PairTerm term = hs::pair_friction(lag, y, eps);
      const double h = 1e-7;
      for (int i = 0; i < 3 * n; ++i) {
        double& c = y[i / 3](i % 3);
        const double keep = c;
        c = keep + h;
        const hs::PairTerm p = hs::pair_friction(lag, y, eps);
        c = keep - h;
        const hs::PairTerm m = hs::pair_friction(lag, y, eps);
        c = keep;
        EXPECT_NEAR(term.gradient(i), (p.energy - m.energy) / (2 * h), 1e-6 * term.gradient.norm())
            << kind << " " << i;
        for (int j = 0; j < 3 * n; ++j)
          EXPECT_NEAR(term.hessian(j, i), (p.gradient(j) - m.gradient(j)) / (2 * h),
                      1e-6 * term.hessian.norm())
              << kind << " " << i << " " << j;
      }
      Vector3d sum = Vector3d::Zero();
      for (int k = 0; k < n; ++k) sum += term.gradient.segment<3>(3 * k);
      EXPECT_NEAR(sum.norm(), 0, 1e-14) << kind;
      const Vector3d on_node = term.gradient.head<3>();
      EXPECT_NEAR(on_node.dot(lag.normal), 0, 1e-14) << kind;
      if (slip > eps) {
        EXPECT_NEAR(on_node.norm(), mu * lambda, 1e-12) << kind;
        EXPECT_NEAR(on_node.normalized().dot(dir), 1, 1e-12) << kind;
      } else {
        EXPECT_LT(on_node.norm(), mu * lambda) << kind;
      }
      Eigen::SelfAdjointEigenSolver<hs::PairMatrix> eig(term.hessian);
      EXPECT_GE(eig.eigenvalues().minCoeff(), -1e-9 * term.hessian.norm()) << kind;
      // The next step starts from the slip, or eps_v of it.
      const Vector3d carried = hs::pair_slip(lag, y);
      EXPECT_NEAR((carried - slip * dir).norm(), 0, 1e-12) << kind;
      const hs::PairFrictionLag next =
          hs::pair_friction_lag(nodes, y, n, 7, mu, lambda, carried, eps);
      EXPECT_NEAR(hs::pair_slip(next, y).norm(), std::min(slip, eps), 1e-9 * slip) << kind;
    }
  }
}
