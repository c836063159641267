#include "control/actuation_qp.hpp"

#include <algorithm>
#include <cmath>

#include "control/qp.hpp"

namespace hs {

ActuationChange solve_actuation_qp(const Eigen::MatrixXd& W, const Eigen::VectorXd& delta,
                                   const Eigen::MatrixXd& growth,
                                   const std::vector<ActuatorConfig>& bounds,
                                   const std::vector<ActuatorPosition>& at, double regularization) {
  const int n = static_cast<int>(bounds.size());
  Eigen::MatrixXd H = W.transpose() * W;
  const double scale = std::max(H.trace() / std::max(n, 1), 1e-300);
  H += regularization * scale * Eigen::MatrixXd::Identity(n, n);
  const Eigen::VectorXd f = W.transpose() * delta;
  std::vector<Eigen::RowVectorXd> rows;
  std::vector<double> rhs;
  std::vector<int> owner;    // actuator of each constraint row
  std::vector<double> sign;  // a bound on the actuator's change alone: its sign; else 0
  auto bound = [&](const Eigen::RowVectorXd& row, double lower, int a, double on_change = 0) {
    if (std::isfinite(lower) && lower > -1e299) {
      rows.push_back(row);
      rhs.push_back(lower);
      owner.push_back(a);
      sign.push_back(on_change);
    }
  };
  for (int a = 0; a < n; ++a) {
    const ActuatorConfig& b = bounds[a];
    const double lambda = at[a].multiplier, origin = at[a].origin, grown = at[a].grown;
    Eigen::RowVectorXd unit = Eigen::RowVectorXd::Zero(n);
    unit(a) = 1;
    bound(unit, b.min_multiplier - lambda, a, 1);
    bound(-unit, lambda - b.max_multiplier, a, -1);
    bound(unit, origin - b.max_multiplier_step - lambda, a, 1);
    bound(-unit, lambda - origin - b.max_multiplier_step, a, -1);
    bound(growth.row(a), b.min_measure_change - grown, a);
    bound(-growth.row(a), grown - b.max_measure_change, a);
  }
  Eigen::MatrixXd A(rows.size(), n);
  Eigen::VectorXd bvec(rows.size());
  for (size_t r = 0; r < rows.size(); ++r) {
    A.row(r) = rows[r];
    bvec(r) = rhs[r];
  }
  const QpResult qp = solve_qp(H, f, A, bvec);
  ActuationChange out;
  out.solved = qp.solved;
  out.status = qp.status;
  out.dl = Eigen::VectorXd::Zero(n);
  if (qp.solved) {
    out.dl = qp.x;
    out.kkt_residual = qp.kkt_residual;
    // An actuator at a bound of its own is put on it exactly, and one past it by less than
    // the QP's tolerance (which leaves such a row inactive) is put back on it: the QP meets
    // its rows to round-off, which left a pressure bound of 0 as 1e-11 Pa in the reports.
    for (int r : qp.active)
      if (sign[r] != 0) out.dl(owner[r]) = sign[r] * rhs[r];
    for (size_t r = 0; r < rows.size(); ++r)
      if (sign[r] != 0 && sign[r] * out.dl(owner[r]) < rhs[r]) out.dl(owner[r]) = sign[r] * rhs[r];
  }
  out.saturated.assign(n, false);
  for (int r : qp.active) out.saturated[owner[r]] = true;
  return out;
}

}  // namespace hs
