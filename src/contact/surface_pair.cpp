#include "contact/surface_pair.hpp"

#include <algorithm>
#include <unsupported/Eigen/AutoDiff>

#include "contact/barrier.hpp"

namespace hs {
namespace {

template <class T>
using Vec3 = Eigen::Matrix<T, 3, 1>;

template <class T>
T squared_distance(const Vec3<T>* x, int n) {
  if (n == 2) return (x[0] - x[1]).squaredNorm();
  if (n == 3) return (x[1] - x[0]).cross(x[2] - x[0]).squaredNorm() / (x[2] - x[1]).squaredNorm();
  const Vec3<T> normal = (x[2] - x[1]).cross(x[3] - x[1]);
  const T h = (x[0] - x[1]).dot(normal);
  return h * h / normal.squaredNorm();
}

// The line-line distance's square: the two edges' separation along their common normal.
template <class T>
T line_line_squared_distance(const Vec3<T>* x) {
  const Vec3<T> normal = (x[1] - x[0]).cross(x[3] - x[2]);
  const T h = (x[2] - x[0]).dot(normal);
  return h * h / normal.squaredNorm();
}

// f(x) with its gradient and Hessian over the 3 N coordinates of x[0 .. N-1], by nested
// forward differentiation.
template <int N, class F>
void derivatives(const Eigen::Vector3d* x, F&& f, double& value, PairVector& gradient,
                 PairMatrix& hessian) {
  constexpr int M = 3 * N;
  using Inner = Eigen::AutoDiffScalar<Eigen::Matrix<double, M, 1>>;
  using Outer = Eigen::AutoDiffScalar<Eigen::Matrix<Inner, M, 1>>;
  Vec3<Outer> y[N];
  for (int a = 0; a < N; ++a)
    for (int d = 0; d < 3; ++d) {
      const int k = 3 * a + d;
      y[a](d).value() = Inner(x[a](d), M, k);
      y[a](d).derivatives().resize(M);
      for (int j = 0; j < M; ++j)
        y[a](d).derivatives()(j) = Inner(j == k ? 1.0 : 0.0, Eigen::Matrix<double, M, 1>::Zero());
    }
  const Outer s = f(y);
  value = s.value().value();
  gradient.setZero();
  hessian.setZero();
  for (int i = 0; i < M; ++i) {
    gradient(i) = s.derivatives()(i).value();
    for (int j = 0; j < M; ++j) hessian(i, j) = s.derivatives()(i).derivatives()(j);
  }
}

template <int N>
void squared_distance_derivatives(const Eigen::Vector3d* x, double& value, PairVector& gradient,
                                  PairMatrix& hessian) {
  derivatives<N>(
      x, [](const auto* y) { return squared_distance(y, N); }, value, gradient, hessian);
}

// The Hessian projected onto the semi-definite matrices in its first m rows and columns.
void project_semidefinite(PairMatrix& hessian, int m) {
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(hessian.topLeftCorner(m, m));
  const Eigen::VectorXd lambda = eig.eigenvalues().cwiseMax(0.0);
  hessian.topLeftCorner(m, m) =
      eig.eigenvectors() * lambda.asDiagonal() * eig.eigenvectors().transpose();
}

}  // namespace

// The regions of p's projection onto the triangle's plane, as in the closest-point test of
// real-time collision detection: vertex, edge or face by the signs of barycentric quantities.
TriangleFeature nearest_feature(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  auto vertex = [](int i) { return TriangleFeature{1, {i, 0, 0}}; };
  auto edge = [](int i, int j) { return TriangleFeature{2, {i, j, 0}}; };
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a, bp = p - b, cp = p - c;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return vertex(0);
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return vertex(1);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return edge(0, 1);
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return vertex(2);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return edge(0, 2);
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return edge(1, 2);
  return TriangleFeature{};
}

double feature_squared_distance(const Eigen::Vector3d* x, int n) { return squared_distance(x, n); }

PairTerm pair_barrier(const Eigen::Vector3d* x, int n, double area, const ContactBarrier& barrier,
                      bool project) {
  double s = 0;
  PairVector g;
  PairMatrix H;
  if (n == 2) squared_distance_derivatives<2>(x, s, g, H);
  if (n == 3) squared_distance_derivatives<3>(x, s, g, H);
  if (n == 4) squared_distance_derivatives<4>(x, s, g, H);
  PairTerm t;
  t.distance = std::sqrt(s);
  const BarrierValue b = contact_barrier(t.distance, barrier.distance);
  const double scale = barrier.stiffness * area, d = t.distance;
  // E(s) = scale b(sqrt s): E' = scale b' / (2 d), E'' = scale (b'' - b' / d) / (4 d^2).
  const double e1 = scale * b.slope / (2 * d),
               e2 = scale * (b.curvature - b.slope / d) / (4 * d * d);
  t.energy = scale * b.value;
  t.gradient = e1 * g;
  t.hessian = e1 * H + e2 * g * g.transpose();
  if (project && b.slope != 0) project_semidefinite(t.hessian, 3 * n);
  return t;
}

// The closest points of the two segments as in real-time collision detection's segment-segment
// test: a parameter clamped to an end of its segment names that vertex. Lines within 1e-12 of
// parallel take a's first vertex (their line-line distance has no direction there).
EdgeFeature nearest_edge_feature(const Eigen::Vector3d* x) {
  const Eigen::Vector3d d1 = x[1] - x[0], d2 = x[3] - x[2], r = x[0] - x[2];
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), b = d1.dot(d2), c = d1.dot(r),
               f = d2.dot(r), denom = a * e - b * b;
  double s = denom > 1e-12 * a * e ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
  double t = (b * s + f) / e;
  if (t <= 0) {
    t = 0;
    s = std::clamp(-c / a, 0.0, 1.0);
  } else if (t >= 1) {
    t = 1;
    s = std::clamp((b - c) / a, 0.0, 1.0);
  }
  const bool s_end = s == 0 || s == 1, t_end = t == 0 || t == 1;
  const int va = s == 1 ? 1 : 0, vb = t == 1 ? 3 : 2;
  if (!s_end && !t_end) return EdgeFeature{};
  if (!t_end) return EdgeFeature{3, {va, 2, 3, 0}};
  if (!s_end) return EdgeFeature{3, {vb, 0, 1, 0}};
  return EdgeFeature{2, {va, vb, 0, 0}};
}

double edge_squared_distance(const Eigen::Vector3d* x, const EdgeFeature& f) {
  if (f.count == 4) return line_line_squared_distance(x);
  const Eigen::Vector3d y[4] = {x[f.vertex[0]], x[f.vertex[1]], x[f.vertex[2]], x[f.vertex[3]]};
  return squared_distance(y, f.count);
}

void edge_feature_weights(const Eigen::Vector3d* x, const EdgeFeature& f, double* w) {
  std::fill(w, w + 4, 0.0);
  if (f.count == 4) {
    const Eigen::Vector3d d1 = x[1] - x[0], d2 = x[3] - x[2], r = x[0] - x[2];
    const double a = d1.squaredNorm(), e = d2.squaredNorm(), b = d1.dot(d2), c = d1.dot(r),
                 g = d2.dot(r);
    const double s = (b * g - c * e) / (a * e - b * b), t = (b * s + g) / e;
    w[0] = 1 - s;
    w[1] = s;
    w[2] = t - 1;
    w[3] = -t;
    return;
  }
  // A vertex of a (sign +1) or of b (-1) less its nearest point on the other's line or vertex.
  const int v = f.vertex[0];
  const double sign = v < 2 ? 1 : -1;
  w[v] = sign;
  if (f.count == 2) {
    w[f.vertex[1]] = -sign;
    return;
  }
  const Eigen::Vector3d e = x[f.vertex[2]] - x[f.vertex[1]];
  const double t = (x[v] - x[f.vertex[1]]).dot(e) / e.squaredNorm();
  w[f.vertex[1]] = -sign * (1 - t);
  w[f.vertex[2]] = -sign * t;
}

namespace {

// d^2 of the feature pair over the 12 coordinates of the two edges.
void edge_distance_derivatives(const Eigen::Vector3d* x, const EdgeFeature& f, double& value,
                               PairVector& gradient, PairMatrix& hessian) {
  if (f.count == 4) {
    derivatives<4>(
        x, [](const auto* y) { return line_line_squared_distance(y); }, value, gradient, hessian);
    return;
  }
  const Eigen::Vector3d y[4] = {x[f.vertex[0]], x[f.vertex[1]], x[f.vertex[2]], x[f.vertex[3]]};
  PairVector g;
  PairMatrix H;
  if (f.count == 3) squared_distance_derivatives<3>(y, value, g, H);
  if (f.count == 2) squared_distance_derivatives<2>(y, value, g, H);
  gradient.setZero();
  hessian.setZero();
  for (int i = 0; i < f.count; ++i) {
    gradient.segment<3>(3 * f.vertex[i]) = g.segment<3>(3 * i);
    for (int j = 0; j < f.count; ++j)
      hessian.block<3, 3>(3 * f.vertex[i], 3 * f.vertex[j]) = H.block<3, 3>(3 * i, 3 * j);
  }
}

}  // namespace

// E = k m(c) beta(s), s = d^2, beta(s) = b(sqrt s), k = kappa w (w here the pair's weight):
//   dE = k (m' beta dc + m beta' ds),
//   d2E = k (m'' beta dc dc^T + m' beta d2c + m' beta' (dc ds^T + ds dc^T)
//            + m (beta' d2s + beta'' ds ds^T)).
PairTerm edge_pair_barrier(const Eigen::Vector3d* x, const EdgeFeature& f, double weight,
                           double parallel, const ContactBarrier& barrier, bool project) {
  double s = 0;
  PairVector gs;
  PairMatrix Hs;
  edge_distance_derivatives(x, f, s, gs, Hs);
  PairTerm t;
  t.distance = std::sqrt(s);
  const double d = t.distance, k = barrier.stiffness * weight;
  const BarrierValue b = contact_barrier(d, barrier.distance);
  const double beta1 = b.slope / (2 * d), beta2 = (b.curvature - b.slope / d) / (4 * d * d);
  const double cross = (x[1] - x[0]).cross(x[3] - x[2]).squaredNorm();
  if (cross >= parallel) {
    t.energy = k * b.value;
    t.gradient = k * beta1 * gs;
    t.hessian = k * (beta1 * Hs + beta2 * gs * gs.transpose());
  } else {
    double c = 0;
    PairVector gc;
    PairMatrix Hc;
    derivatives<4>(
        x, [](const auto* y) { return (y[1] - y[0]).cross(y[3] - y[2]).squaredNorm(); }, c, gc, Hc);
    // The quintic smoothstep over eps/2 < c < eps: C2, zero below.
    const double w = 0.5 * parallel, r = std::max(0.0, (c - w) / w);
    const double m = r * r * r * (r * (6 * r - 15) + 10), m1 = 30 * r * r * (r - 1) * (r - 1) / w,
                 m2 = 60 * r * (2 * r * r - 3 * r + 1) / (w * w);
    t.energy = k * m * b.value;
    t.gradient = k * (m1 * b.value * gc + m * beta1 * gs);
    t.hessian = k * (m2 * b.value * gc * gc.transpose() + m1 * b.value * Hc +
                     m1 * beta1 * (gc * gs.transpose() + gs * gc.transpose()) +
                     m * (beta1 * Hs + beta2 * gs * gs.transpose()));
  }
  if (project && b.slope != 0) project_semidefinite(t.hessian, 12);
  return t;
}

}  // namespace hs
