#include "fem/quadrature.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace hs {

void gauss_jacobi(int n, int alpha, std::vector<double>& points, std::vector<double>& weights) {
  // Jacobi polynomials on [-1, 1] for (1 - t)^alpha (1 + t)^0: the nodes are the eigenvalues of
  // the symmetric tridiagonal Jacobi matrix of the three-term recurrence, the weights mu0 times
  // the squared first components of the eigenvectors.
  const double a = alpha, b = 0.0;
  Eigen::MatrixXd T = Eigen::MatrixXd::Zero(n, n);
  for (int k = 0; k < n; ++k) {
    const double s = 2.0 * k + a + b;
    T(k, k) = (k == 0) ? (b - a) / (a + b + 2.0) : (b * b - a * a) / (s * (s + 2.0));
    if (k + 1 < n) {
      const double m = k + 1.0, sm = 2.0 * m + a + b;
      const double off = std::sqrt(4.0 * m * (m + a) * (m + b) * (m + a + b) /
                                   (sm * sm * (sm + 1.0) * (sm - 1.0)));
      T(k, k + 1) = T(k + 1, k) = off;
    }
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(T);
  const double mu0 = std::pow(2.0, a + b + 1.0) / (a + 1.0);  // int_{-1}^{1} (1 - t)^alpha dt
  points.resize(n);
  weights.resize(n);
  for (int i = 0; i < n; ++i) {
    // x = (1 + t)/2 on [0, 1]: (1 - x)^alpha dx = 2^-(alpha+1) (1 - t)^alpha dt.
    points[i] = 0.5 * (1.0 + eig.eigenvalues()(i));
    const double v0 = eig.eigenvectors()(0, i);
    weights[i] = mu0 * v0 * v0 / std::pow(2.0, a + 1.0);
  }
}

namespace {

int points_per_direction(int degree) { return degree / 2 + 1; }  // 2n - 1 >= degree

TetQuadrature make_tet_rule(int degree) {
  TetQuadrature q;
  if (degree <= 1) {  // centroid
    q.points = {Eigen::Vector3d(0.25, 0.25, 0.25)};
    q.weights = {1.0 / 6.0};
  } else if (degree == 2) {  // 4 points: a = (5 - sqrt 5)/20, b = (5 + 3 sqrt 5)/20
    const double a = (5.0 - std::sqrt(5.0)) / 20.0, b = (5.0 + 3.0 * std::sqrt(5.0)) / 20.0;
    q.points = {{a, a, a}, {b, a, a}, {a, b, a}, {a, a, b}};
    q.weights.assign(4, 1.0 / 24.0);
  } else {
    const int n = points_per_direction(degree);
    std::vector<double> xu, wu, xv, wv, xw, ww;
    gauss_jacobi(n, 2, xu, wu);
    gauss_jacobi(n, 1, xv, wv);
    gauss_jacobi(n, 0, xw, ww);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        for (int k = 0; k < n; ++k) {
          const double u = xu[i], v = xv[j], w = xw[k];
          q.points.emplace_back(u, (1 - u) * v, (1 - u) * (1 - v) * w);
          q.weights.push_back(wu[i] * wv[j] * ww[k]);
        }
  }
  return q;
}

TriQuadrature make_tri_rule(int degree) {
  TriQuadrature q;
  if (degree <= 1) {
    q.points = {Eigen::Vector2d(1.0 / 3.0, 1.0 / 3.0)};
    q.weights = {0.5};
  } else if (degree == 2) {
    q.points = {{1.0 / 6.0, 1.0 / 6.0}, {2.0 / 3.0, 1.0 / 6.0}, {1.0 / 6.0, 2.0 / 3.0}};
    q.weights.assign(3, 1.0 / 6.0);
  } else {
    const int n = points_per_direction(degree);
    std::vector<double> xu, wu, xv, wv;
    gauss_jacobi(n, 1, xu, wu);
    gauss_jacobi(n, 0, xv, wv);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        q.points.emplace_back(xu[i], (1 - xu[i]) * xv[j]);
        q.weights.push_back(wu[i] * wv[j]);
      }
  }
  return q;
}

void check_degree(int degree) {
  if (degree < 0 || degree > kMaxQuadratureDegree)
    throw std::invalid_argument("quadrature degree " + std::to_string(degree) + " is outside 0.." +
                                std::to_string(kMaxQuadratureDegree));
}

}  // namespace

const TetQuadrature& tet_quadrature(int degree) {
  check_degree(degree);
  static const std::vector<TetQuadrature> rules = [] {
    std::vector<TetQuadrature> r;
    for (int d = 0; d <= kMaxQuadratureDegree; ++d) r.push_back(make_tet_rule(d));
    return r;
  }();
  return rules[degree];
}

const TriQuadrature& tri_quadrature(int degree) {
  check_degree(degree);
  static const std::vector<TriQuadrature> rules = [] {
    std::vector<TriQuadrature> r;
    for (int d = 0; d <= kMaxQuadratureDegree; ++d) r.push_back(make_tri_rule(d));
    return r;
  }();
  return rules[degree];
}

}  // namespace hs
