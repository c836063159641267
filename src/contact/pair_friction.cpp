#include "contact/pair_friction.hpp"

#include <algorithm>

#include "contact/friction.hpp"

namespace hs {

void feature_weights(const Eigen::Vector3d* x, int n, double* beta) {
  if (n == 2) {
    beta[0] = 1;
    return;
  }
  if (n == 3) {
    const Eigen::Vector3d e = x[2] - x[1];
    const double t = (x[0] - x[1]).dot(e) / e.squaredNorm();
    beta[0] = 1 - t;
    beta[1] = t;
    return;
  }
  // The projection's barycentric coordinates from the normal equations of the triangle's
  // two edge vectors.
  const Eigen::Vector3d e1 = x[2] - x[1], e2 = x[3] - x[1], v = x[0] - x[1];
  const double a = e1.dot(e1), b = e1.dot(e2), c = e2.dot(e2), d = v.dot(e1), e = v.dot(e2);
  const double det = a * c - b * b;
  const double s = (c * d - b * e) / det, t = (a * e - b * d) / det;
  beta[0] = 1 - s - t;
  beta[1] = s;
  beta[2] = t;
}

Eigen::Vector3d pair_slip(const PairFrictionLag& lag, const Eigen::Vector3d* x) {
  Eigen::Vector3d r = Eigen::Vector3d::Zero();
  for (int k = 0; k < lag.count; ++k) r += lag.weight[k] * x[k];
  const Eigen::Vector3d w = r - lag.anchor;
  return w - lag.normal * lag.normal.dot(w);
}

namespace {

// The lag of `count` nodes at x whose weights are set: its normal and anchor.
PairFrictionLag lag_of(PairFrictionLag lag, const int32_t* nodes, const Eigen::Vector3d* x,
                       const Eigen::Vector3d& carried, double eps_v) {
  Eigen::Vector3d r = Eigen::Vector3d::Zero();
  for (int k = 0; k < lag.count; ++k) {
    lag.node[k] = nodes[k];
    r += lag.weight[k] * x[k];
  }
  lag.normal = r.normalized();
  // The slip carried into the new tangent plane at its length, at most eps_v: where the
  // normal has turned (a node moving round an edge), the force starts as large as it ended.
  const Eigen::Vector3d in_plane = carried - lag.normal * lag.normal.dot(carried);
  const double y = in_plane.norm(), keep = std::min(carried.norm(), eps_v);
  lag.anchor = y > 0 ? Eigen::Vector3d(r - keep / y * in_plane) : r;
  return lag;
}

PairFrictionLag unweighted(int count, int32_t face, double mu, double normal_force) {
  PairFrictionLag lag;
  lag.friction = mu;
  lag.count = count;
  lag.face = face;
  lag.normal_force = normal_force;
  return lag;
}

}  // namespace

PairFrictionLag pair_friction_lag(const int32_t* nodes, const Eigen::Vector3d* x, int count,
                                  int32_t face, double mu, double normal_force,
                                  const Eigen::Vector3d& carried, double eps_v) {
  PairFrictionLag lag = unweighted(count, face, mu, normal_force);
  double beta[3];
  feature_weights(x, count, beta);
  for (int k = 1; k < count; ++k) lag.weight[k] = -beta[k - 1];
  return lag_of(lag, nodes, x, carried, eps_v);
}

PairFrictionLag edge_friction_lag(const int32_t* nodes, const Eigen::Vector3d* x,
                                  const EdgeFeature& f, int32_t face, double mu,
                                  double normal_force, const Eigen::Vector3d& carried,
                                  double eps_v) {
  PairFrictionLag lag = unweighted(4, face, mu, normal_force);
  edge_feature_weights(x, f, lag.weight);
  return lag_of(lag, nodes, x, carried, eps_v);
}

PairTerm pair_friction(const PairFrictionLag& lag, const Eigen::Vector3d* x, double eps_v) {
  PairTerm t;
  const double scale = lag.friction * lag.normal_force;
  if (scale == 0) return t;
  const Eigen::Vector3d w = pair_slip(lag, x);
  const SlipPotential f = slip_potential(w.norm(), eps_v);
  const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - lag.normal * lag.normal.transpose();
  const Eigen::Vector3d force = scale * f.slope_over_y * w;
  const Eigen::Matrix3d stiffness = scale * (f.slope_over_y * P + f.g * w * w.transpose());
  t.energy = scale * f.value;
  for (int i = 0; i < lag.count; ++i) {
    t.gradient.segment<3>(3 * i) = lag.weight[i] * force;
    for (int j = 0; j < lag.count; ++j)
      t.hessian.block<3, 3>(3 * i, 3 * j) = lag.weight[i] * lag.weight[j] * stiffness;
  }
  return t;
}

}  // namespace hs
