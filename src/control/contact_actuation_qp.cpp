#include "control/contact_actuation_qp.hpp"

#include <algorithm>
#include <cmath>
#include <set>

namespace hs {
namespace {

// For an active set: the force changes as dforce = E0 + E1 dl (the touching nodes' closing
// their gaps, the others' going to zero).
void affine_forces(const ContactBlocks& k, const std::vector<char>& touching, Eigen::VectorXd& E0,
                   Eigen::MatrixXd& E1) {
  const Eigen::Index N = k.gap.size(), n = k.G_ca.cols();
  E0 = -k.held;
  E1 = Eigen::MatrixXd::Zero(N, n);
  std::vector<Eigen::Index> A;
  for (Eigen::Index c = 0; c < N; ++c)
    if (touching[c]) {
      A.push_back(c);
      E0(c) = 0;
    }
  if (A.empty()) return;
  const Eigen::Index m = static_cast<Eigen::Index>(A.size());
  Eigen::MatrixXd G(m, m), Ga(m, n);
  Eigen::VectorXd rhs(m);
  for (Eigen::Index i = 0; i < m; ++i) {
    for (Eigen::Index j = 0; j < m; ++j) G(i, j) = k.G_cc(A[i], A[j]);
    Ga.row(i) = k.G_ca.row(A[i]);
    rhs(i) = -(k.gap(A[i]) + k.G_cc.row(A[i]).dot(E0));  // E0 is zero on A here
  }
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(G);
  const Eigen::VectorXd p = ldlt.solve(rhs);
  const Eigen::MatrixXd q = ldlt.solve(-Ga);
  for (Eigen::Index i = 0; i < m; ++i) {
    E0(A[i]) = p(i);
    E1.row(A[i]) = q.row(i);
  }
}

}  // namespace

ContactActuation solve_contact_actuation_qp(const ContactBlocks& k,
                                            const std::vector<ActuatorConfig>& bounds,
                                            const std::vector<ActuatorPosition>& at,
                                            double regularization) {
  const Eigen::Index N = k.gap.size(), n = k.G_ca.cols(), r = k.W_a.rows();
  std::vector<char> touching(N);
  for (Eigen::Index c = 0; c < N; ++c) touching[c] = k.held(c) > 0 || k.gap(c) <= k.gap_tolerance;
  std::set<std::vector<char>> seen;
  ContactActuation out;
  bool one_at_a_time = false;
  const int most_passes = 10 * static_cast<int>(N) + 10;
  Eigen::VectorXd force, gap;
  while (true) {
    seen.insert(touching);
    ++out.passes;
    Eigen::VectorXd E0;
    Eigen::MatrixXd E1;
    affine_forces(k, touching, E0, E1);
    // The gaps as g0 + Ggap dl, the effectors as W dl + delta, the measures through growth.
    const Eigen::VectorXd g0 = k.gap + k.G_cc * E0;
    const Eigen::MatrixXd Ggap = k.G_ca + k.G_cc * E1;
    Eigen::MatrixXd W = k.W_a + k.W_c * E1;
    Eigen::VectorXd delta = k.delta + k.W_c * E0;
    for (Eigen::Index row = 0; row < r; ++row) {
      const int c = k.approach[row];
      if (c < 0) continue;
      bool any = false;  // a candidate of its effector touches: its force rows hold
      for (Eigen::Index j = 0; j < N; ++j) any |= touching[j] && k.W_c(row, j) != 0;
      if (any) continue;
      W.row(row) += k.approach_factor(row) * Ggap.row(c);
      delta(row) += k.approach_factor(row) * (g0(c) - k.gap(c));
    }
    std::vector<ActuatorPosition> shifted = at;
    const Eigen::VectorXd grown = k.growth_c * E0;
    for (Eigen::Index a = 0; a < n; ++a) shifted[a].grown += grown(a);
    out.change =
        solve_actuation_qp(W, delta, k.growth_a + k.growth_c * E1, bounds, shifted, regularization);
    out.dforce = E0 + E1 * out.change.dl;
    force = k.held + out.dforce;
    gap = g0 + Ggap * out.change.dl;
    if (!out.change.solved) {  // nothing changes: the actuation's and the forces' changes zero
      out.dforce.setZero();
      force = k.held;
      gap = k.gap;
      break;
    }
    // A touching node that would pull leaves the set, a free one that would enter an
    // obstacle (or reach it) joins it: all at once, or, once a set came back, the first such
    // node alone (the least-index rule, which ends for a positive definite G_cc).
    const double pull = -1e-12 * (1 + force.cwiseAbs().maxCoeff());
    std::vector<char> next = touching;
    for (Eigen::Index c = 0; c < N; ++c) {
      const bool flip = touching[c] ? force(c) < pull : gap(c) <= k.gap_tolerance;
      if (!flip) continue;
      next[c] = !touching[c];
      if (one_at_a_time) break;
    }
    if (next == touching) break;
    if (seen.count(next)) {
      if (one_at_a_time) {
        out.cycled = true;
        break;
      }
      one_at_a_time = true;
      seen.clear();
      continue;
    }
    if (out.passes >= most_passes) {
      out.cycled = true;
      break;
    }
    touching = next;
  }
  out.touching = static_cast<int>(std::count(touching.begin(), touching.end(), 1));
  out.least_gap = N ? gap.minCoeff() : 0;
  out.least_force = N ? force.minCoeff() : 0;
  for (Eigen::Index c = 0; c < N; ++c)
    out.worst_product = std::max(out.worst_product, std::abs(force(c) * gap(c)));
  return out;
}

}  // namespace hs
