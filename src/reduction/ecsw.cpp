#include "reduction/ecsw.hpp"

#include <algorithm>
#include <stdexcept>

namespace hs {
namespace {

// The least-squares weights of the passive columns P: (C_P^T C_P) z = C_P^T b. The normal
// equations square C_P's condition, which costs digits far below the tolerances ECSW is run
// at (1e-2 to 1e-5), and let the Gram matrix grow by one row and column per element added
// (m p per element, where a QR of C_P would cost m p^2 each time).
Eigen::VectorXd passive_solution(const Eigen::MatrixXd& gram, const Eigen::VectorXd& rhs) {
  return gram.ldlt().solve(rhs);
}

// The most elements a fit keeps: a quarter of C's rows, or 256 where that is more (still at
// most a row each: one element a row always meets any tolerance, a basic solution). Each
// element added costs more than the last; the pendulum's fit at 1e-6 held 1,111 elements
// after three minutes.
Eigen::Index most_elements(const Eigen::MatrixXd& C) {
  return std::min({C.cols(), C.rows(), std::max<Eigen::Index>(C.rows() / 4, 256)});
}

}  // namespace

EcswWeights ecsw_weights(const Eigen::MatrixXd& C, const Eigen::VectorXd& b, double tolerance,
                         const std::function<bool()>& interrupted) {
  if (C.rows() != b.size()) throw std::invalid_argument("ecsw_weights: C and b disagree in size");
  if (!C.allFinite() || !b.allFinite())
    throw std::invalid_argument("ecsw_weights: the data is not finite");
  if (!(tolerance > 0 && tolerance < 1))
    throw std::invalid_argument("ecsw_weights: the tolerance must lie in (0, 1)");
  const Eigen::Index n = C.cols();
  const double b_norm = b.norm();
  EcswWeights out;
  if (b_norm == 0) {
    out.converged = true;
    return out;
  }
  std::vector<int> passive;  // columns with a positive weight
  std::vector<char> in_passive(n, 0);
  Eigen::VectorXd w_passive;  // their weights, in the order of `passive`
  Eigen::VectorXd r = b;
  double r_norm = b_norm;
  const Eigen::VectorXd column_norms = C.colwise().norm();
  const Eigen::VectorXd Ctb = C.transpose() * b;
  Eigen::MatrixXd gram(0, 0);  // C_P^T C_P, in the order of `passive`
  const Eigen::Index most = most_elements(C);
  while (r_norm > tolerance * b_norm) {
    if (static_cast<Eigen::Index>(passive.size()) >= most) {
      out.reason = "stopped at " + std::to_string(passive.size()) +
                   " elements, the most a fit of " + std::to_string(C.rows()) + " rows keeps";
      break;
    }
    if (interrupted && interrupted()) {
      out.interrupted = true;
      break;
    }
    // The column along which the residual falls fastest (scaled, so that an element's size
    // does not decide).
    const Eigen::VectorXd g = C.transpose() * r;
    int best = -1;
    double best_value = 0;
    for (Eigen::Index e = 0; e < n; ++e) {
      if (in_passive[e] || column_norms(e) == 0) continue;
      const double value = g(e) / column_norms(e);
      if (value > best_value) {
        best_value = value;
        best = static_cast<int>(e);
      }
    }
    if (best < 0 || best_value <= 1e-14 * b_norm) {
      out.reason = "no element lowers the residual further";
      break;
    }
    // The Gram matrix of the passive columns grows by one row and column.
    const Eigen::Index p0 = static_cast<Eigen::Index>(passive.size());
    Eigen::VectorXd cross(p0);
    for (Eigen::Index i = 0; i < p0; ++i) cross(i) = C.col(passive[i]).dot(C.col(best));
    gram.conservativeResize(p0 + 1, p0 + 1);
    gram.row(p0).head(p0) = cross.transpose();
    gram.col(p0).head(p0) = cross;
    gram(p0, p0) = C.col(best).squaredNorm();
    passive.push_back(best);
    in_passive[best] = 1;
    w_passive.conservativeResize(p0 + 1);
    w_passive(p0) = 0;
    // Lawson-Hanson's inner loop: move towards the passive set's least-squares weights, and
    // drop the columns whose weight would turn negative.
    for (;;) {
      const Eigen::Index p = static_cast<Eigen::Index>(passive.size());
      Eigen::VectorXd rhs(p);
      for (Eigen::Index i = 0; i < p; ++i) rhs(i) = Ctb(passive[i]);
      const Eigen::VectorXd z = passive_solution(gram, rhs);
      if ((z.array() > 0).all()) {
        w_passive = z;
        break;
      }
      double alpha = 1;
      for (Eigen::Index i = 0; i < p; ++i)
        if (z(i) <= 0) alpha = std::min(alpha, w_passive(i) / (w_passive(i) - z(i)));
      w_passive += alpha * (z - w_passive);
      std::vector<Eigen::Index> kept;
      const double floor = 1e-14 * std::max(1.0, w_passive.cwiseAbs().maxCoeff());
      for (Eigen::Index i = 0; i < p; ++i) {
        if (w_passive(i) > floor)
          kept.push_back(i);
        else
          in_passive[passive[i]] = 0;
      }
      const Eigen::Index q = static_cast<Eigen::Index>(kept.size());
      std::vector<int> passive_kept(q);
      Eigen::VectorXd w_kept(q);
      Eigen::MatrixXd gram_kept(q, q);
      for (Eigen::Index i = 0; i < q; ++i) {
        passive_kept[i] = passive[kept[i]];
        w_kept(i) = w_passive(kept[i]);
        for (Eigen::Index j = 0; j < q; ++j) gram_kept(i, j) = gram(kept[i], kept[j]);
      }
      passive = std::move(passive_kept);
      w_passive = w_kept;
      gram = gram_kept;
      if (passive.empty()) break;
    }
    r = b;
    for (size_t i = 0; i < passive.size(); ++i) r -= w_passive(i) * C.col(passive[i]);
    r_norm = r.norm();
  }
  std::vector<size_t> order(passive.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t c) { return passive[a] < passive[c]; });
  for (size_t i : order) {
    out.elements.push_back(passive[i]);
    out.weights.push_back(w_passive(i));
  }
  out.relative_residual = r_norm / b_norm;
  out.converged = r_norm <= tolerance * b_norm;
  return out;
}

}  // namespace hs
