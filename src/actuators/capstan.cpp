#include "actuators/capstan.hpp"

#include <algorithm>
#include <cmath>

namespace hs {
namespace {

using Vec3 = std::array<double, 3>;

double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// (I - e e^T) v / l: the change of the unit vector e of a segment of length l when its end
// moves by v.
Vec3 project(const Vec3& e, double l, const Vec3& v) {
  const double ev = dot(e, v);
  return {(v[0] - ev * e[0]) / l, (v[1] - ev * e[1]) / l, (v[2] - ev * e[2]) / l};
}

}  // namespace

CapstanForces capstan_forces(const std::vector<Vec3>& p, double mu, bool with_jacobian) {
  const size_t points = p.size(), n = points - 1;  // n segments
  std::vector<Vec3> e(n);
  std::vector<double> l(n);
  for (size_t k = 0; k < n; ++k) {
    const Vec3 d = {p[k + 1][0] - p[k][0], p[k + 1][1] - p[k][1], p[k + 1][2] - p[k][2]};
    l[k] = std::sqrt(dot(d, d));
    for (int a = 0; a < 3; ++a) e[k][a] = d[a] / l[k];
  }
  // Turning angle at each interior point, and the wrap between each segment and the motor.
  std::vector<double> theta(points, 0.0), wrap(n, 0.0);
  for (size_t j = 1; j < n; ++j) theta[j] = std::acos(std::clamp(dot(e[j - 1], e[j]), -1.0, 1.0));
  for (size_t k = n - 1; k-- > 0;) wrap[k] = wrap[k + 1] + theta[k + 1];

  CapstanForces out;
  out.force.assign(points, {0, 0, 0});
  out.tension.resize(n);
  for (size_t k = 0; k < n; ++k) {
    const double tau = out.tension[k] = std::exp(-mu * wrap[k]);
    for (int a = 0; a < 3; ++a) {
      out.force[k][a] += tau * e[k][a];
      out.force[k + 1][a] -= tau * e[k][a];
    }
  }
  if (!with_jacobian) return out;

  const size_t dim = 3 * points;
  out.jacobian.assign(dim * dim, 0.0);
  // J(i, m) += s * outer(x, y): the block of dF_i/dp_m.
  auto add_outer = [&](size_t i, size_t m, double s, const Vec3& x, const Vec3& y) {
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) out.jacobian[(3 * i + a) * dim + 3 * m + b] += s * x[a] * y[b];
  };
  // J(i, m) += s (I - e e^T) / l.
  auto add_projector = [&](size_t i, size_t m, double s, size_t k) {
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        out.jacobian[(3 * i + a) * dim + 3 * m + b] += s * ((a == b) - e[k][a] * e[k][b]) / l[k];
  };
  // d theta_j / dp at its three points: +a_j, b_j - a_j, -b_j with
  // a_j = P_{j-1} e_j / sin theta_j, b_j = P_j e_{j-1} / sin theta_j.
  std::vector<std::array<Vec3, 3>> dtheta(points);
  std::vector<bool> turns(points, false);
  for (size_t j = 1; j < n; ++j) {
    const double s = std::sin(theta[j]);
    if (!(s > 1e-12)) continue;
    turns[j] = true;
    Vec3 a = project(e[j - 1], l[j - 1], e[j]), b = project(e[j], l[j], e[j - 1]);
    for (int c = 0; c < 3; ++c) {
      a[c] /= s;
      b[c] /= s;
    }
    dtheta[j] = {a, Vec3{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, Vec3{-b[0], -b[1], -b[2]}};
  }
  for (size_t k = 0; k < n; ++k) {
    const double tau = out.tension[k];
    // tau_k de_k: de_k = P_k (dp_{k+1} - dp_k), on F_k with +, on F_{k+1} with -.
    add_projector(k, k + 1, tau, k);
    add_projector(k, k, -tau, k);
    add_projector(k + 1, k + 1, -tau, k);
    add_projector(k + 1, k, tau, k);
    // e_k dtau_k: dtau_k = -mu tau_k sum_{j > k} dtheta_j.
    for (size_t j = k + 1; j < n; ++j) {
      if (!turns[j]) continue;
      for (size_t q = 0; q < 3; ++q) {
        add_outer(k, j - 1 + q, -mu * tau, e[k], dtheta[j][q]);
        add_outer(k + 1, j - 1 + q, mu * tau, e[k], dtheta[j][q]);
      }
    }
  }
  return out;
}

}  // namespace hs
