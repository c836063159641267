#include "contact/surface_pair.hpp"

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

// d^2 with its gradient and Hessian over the 3 N coordinates, by nested forward differentiation.
template <int N>
void squared_distance_derivatives(const Eigen::Vector3d* x, double& value, PairVector& gradient,
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
  const Outer s = squared_distance(y, N);
  value = s.value().value();
  gradient.setZero();
  hessian.setZero();
  for (int i = 0; i < M; ++i) {
    gradient(i) = s.derivatives()(i).value();
    for (int j = 0; j < M; ++j) hessian(i, j) = s.derivatives()(i).derivatives()(j);
  }
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
  if (project && b.slope != 0) {
    const int m = 3 * n;
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(t.hessian.topLeftCorner(m, m));
    const Eigen::VectorXd lambda = eig.eigenvalues().cwiseMax(0.0);
    t.hessian.topLeftCorner(m, m) =
        eig.eigenvectors() * lambda.asDiagonal() * eig.eigenvectors().transpose();
  }
  return t;
}

}  // namespace hs
