// Goldfarb-Idnani dual active-set method (Math. Programming 27, 1983), written with
// explicit small matrices instead of the paper's updated QR factors: the problems here
// have a few unknowns, so each iteration refactors N^T H^-1 N (k x k, k <= n) from the
// Cholesky factor of H. Clear and exact enough; docs/control.md says why it is our own.
#include "control/qp.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace hs {
namespace {

bool all_finite(const Eigen::MatrixXd& m) { return m.allFinite(); }

// Scale of the terms of row i of A x - b, for relative tolerances: x_size is the size of
// the QP's steps (the larger of |x| and |H^-1 f|), so that a bound met at x = 0 with
// b = 0 is not measured against zero.
double row_scale(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, double x_size, int i) {
  return std::abs(b(i)) + A.row(i).cwiseAbs().sum() * x_size;
}

double step_size(const Eigen::MatrixXd& H, const Eigen::VectorXd& f, const Eigen::VectorXd& x) {
  double size = x.size() ? x.cwiseAbs().maxCoeff() : 0.0;
  const Eigen::LLT<Eigen::MatrixXd> chol(H);
  if (x.size() && chol.info() == Eigen::Success) {
    const Eigen::VectorXd free = chol.solve(f);
    if (free.allFinite()) size = std::max(size, free.cwiseAbs().maxCoeff());
  }
  return size;
}

}  // namespace

double qp_kkt_residual(const Eigen::MatrixXd& H, const Eigen::VectorXd& f, const Eigen::MatrixXd& A,
                       const Eigen::VectorXd& b, const Eigen::VectorXd& x,
                       const Eigen::VectorXd& mu) {
  constexpr double tiny = std::numeric_limits<double>::min();
  const Eigen::VectorXd stationarity = H * x + f - A.transpose() * mu;
  const Eigen::VectorXd size =
      H.cwiseAbs() * x.cwiseAbs() + f.cwiseAbs() + A.transpose().cwiseAbs() * mu.cwiseAbs();
  double r = stationarity.cwiseAbs().maxCoeff() / (size.maxCoeff() + tiny);
  if (x.size() == 0) r = 0;
  const double mu_max = mu.size() ? mu.cwiseAbs().maxCoeff() : 0.0;
  const double x_size = step_size(H, f, x);
  for (int i = 0; i < A.rows(); ++i) {
    const double slack = A.row(i).dot(x) - b(i);
    const double scale = row_scale(A, b, x_size, i) + tiny;
    r = std::max(r, std::max(-slack, 0.0) / scale);
    r = std::max(r, std::abs(mu(i) * slack) / (std::abs(mu(i)) * scale + tiny));
    r = std::max(r, std::max(-mu(i), 0.0) / (mu_max + tiny));
  }
  return r;
}

QpResult solve_qp(const Eigen::MatrixXd& H, const Eigen::VectorXd& f, const Eigen::MatrixXd& A,
                  const Eigen::VectorXd& b) {
  const int n = static_cast<int>(f.size());
  const int m = static_cast<int>(b.size());
  if (H.rows() != n || H.cols() != n || A.rows() != m || (m > 0 && A.cols() != n))
    throw std::invalid_argument("solve_qp: dimensions of H, f, A, b do not agree");

  QpResult out;
  out.x = Eigen::VectorXd::Zero(n);
  out.multipliers = Eigen::VectorXd::Zero(m);
  if (!all_finite(H) || !all_finite(f) || !all_finite(A) || !all_finite(b)) {
    out.status = "non-finite data (NaN or Inf) in the QP";
    return out;
  }
  if ((H - H.transpose()).cwiseAbs().maxCoeff() > 1e-12 * H.cwiseAbs().maxCoeff()) {
    out.status = "H is not symmetric";
    return out;
  }
  const Eigen::LLT<Eigen::MatrixXd> chol(H);
  if (n > 0 && (chol.info() != Eigen::Success || !chol.matrixL().toDenseMatrix().allFinite() ||
                chol.matrixLLT().diagonal().minCoeff() <= 0)) {
    out.status = "H is not positive definite";
    return out;
  }

  // A zero row is the constant constraint 0 >= b_i: void, or impossible.
  std::vector<double> norm(m);
  for (int i = 0; i < m; ++i) {
    norm[i] = A.row(i).norm();
    if (norm[i] == 0 && b(i) > 0) {
      out.status =
          "infeasible: constraint row " + std::to_string(i) + " is 0 >= " + std::to_string(b(i));
      return out;
    }
  }

  Eigen::VectorXd x = n ? Eigen::VectorXd(chol.solve(-f)) : Eigen::VectorXd();
  Eigen::VectorXd mu = Eigen::VectorXd::Zero(m);
  std::vector<int> active;  // the rows held as equalities, linearly independent
  const int max_iterations = 10 * (n + m) + 50;
  auto finish = [&](bool solved, std::string status) {
    out.x = x;
    out.multipliers = mu;
    out.solved = solved;
    out.status = std::move(status);
    out.kkt_residual = qp_kkt_residual(H, f, A, b, x, mu);
    for (int i : active)
      if (mu(i) > 0) out.active.push_back(i);
    return out;
  };

  const double x_size = step_size(H, f, x);
  while (true) {
    // The most violated constraint, measured as a distance (slack over the row's norm).
    int p = -1;
    double worst = 0;
    for (int i = 0; i < m; ++i) {
      if (norm[i] == 0) continue;
      const double slack = A.row(i).dot(x) - b(i);
      if (slack >= -1e-13 * row_scale(A, b, std::max(x_size, x.cwiseAbs().maxCoeff()), i)) continue;
      if (-slack / norm[i] > worst) {
        worst = -slack / norm[i];
        p = i;
      }
    }
    if (p < 0) return finish(true, "optimal");

    const Eigen::VectorXd a = A.row(p).transpose();
    const Eigen::VectorXd Hinv_a = chol.solve(a);
    double mu_p = 0;  // the multiplier p collects while it is being added
    while (true) {
      if (++out.iterations > max_iterations) return finish(false, "iteration limit");
      const int k = static_cast<int>(active.size());
      // Primal direction z = H^-1 (I - N N*) a and dual direction r = N* a, with
      // N* = (N^T H^-1 N)^-1 N^T H^-1 the H^-1-weighted pseudo-inverse of N = A_active^T.
      Eigen::VectorXd r(k), z = Hinv_a;
      if (k > 0) {
        Eigen::MatrixXd N(n, k);
        for (int j = 0; j < k; ++j) N.col(j) = A.row(active[j]).transpose();
        const Eigen::MatrixXd Hinv_N = chol.solve(N);
        r = (N.transpose() * Hinv_N).ldlt().solve(Hinv_N.transpose() * a);
        z -= Hinv_N * r;
      }
      // z = 0 when a lies in the span of the active normals (then only multipliers move).
      const double curvature = z.dot(a);
      const bool dependent = curvature <= 1e-12 * a.dot(Hinv_a);

      // Largest dual step that keeps every active multiplier >= 0 (blocking row: drop).
      double t_dual = std::numeric_limits<double>::infinity();
      int drop = -1;
      for (int j = 0; j < k; ++j)
        if (r(j) > 0 && mu(active[j]) / r(j) < t_dual) {
          t_dual = mu(active[j]) / r(j);
          drop = j;
        }
      if (dependent && drop < 0)
        return finish(false, "infeasible: constraint row " + std::to_string(p) +
                                 " cannot hold together with the active rows");
      const double slack = a.dot(x) - b(p);
      const double t_full = dependent ? std::numeric_limits<double>::infinity()
                                      : -slack / curvature;  // makes row p active
      const double t = std::min(t_dual, t_full);

      if (!dependent) x += t * z;
      for (int j = 0; j < k; ++j) mu(active[j]) -= t * r(j);
      mu_p += t;
      if (t == t_full) {
        mu(p) = mu_p;
        active.push_back(p);
        break;
      }
      mu(active[drop]) = 0;
      active.erase(active.begin() + drop);
    }
  }
}

}  // namespace hs
