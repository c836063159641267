// Steps 2 and 3 of the controller's step (solvers/inverse_controller.hpp): the compliance W of
// the targeted effectors and the volume growth of each actuator from the responses, and the
// dense QP for the pressure changes under the actuators' bounds.
#include <algorithm>
#include <cmath>

#include "control/qp.hpp"
#include "solvers/inverse_controller.hpp"

namespace hs {

// Effector rows (weighted, controlled directions of the targeted effectors) and volumes.
void InverseController::compliance_rows(Vec u, const std::vector<ControlTarget>& targets,
                                        Eigen::MatrixXd& W, Eigen::VectorXd& delta,
                                        Eigen::MatrixXd& growth) {
  const int n = num_actuators();
  const std::vector<double> x_free = effectors_.positions(u);
  std::vector<double> rows_delta;
  std::vector<std::vector<double>> rows_W;
  std::vector<PetscScalar> wdots(n);
  for (const auto& t : targets) {
    const int e = effectors_.index(t.effector);
    const auto& ec = effectors_.config(e);
    for (int d = 0; d < 3; ++d) {
      if (!ec.directions[d]) continue;
      HS_PETSC(VecMDot(effectors_.row(e, d), n, response_.data(), wdots.data()));
      std::vector<double> r(n);
      for (int a = 0; a < n; ++a) r[a] = ec.weight * wdots[a];
      rows_W.push_back(r);
      rows_delta.push_back(ec.weight * (x_free[3 * e + d] - t.position[d]));
    }
  }
  W.resize(rows_W.size(), n);
  growth.resize(n, n);
  delta.resize(rows_W.size());
  for (size_t r = 0; r < rows_W.size(); ++r) {
    for (int a = 0; a < n; ++a) W(r, a) = rows_W[r][a];
    delta(r) = rows_delta[r];
  }
  for (int a = 0; a < n; ++a) {
    HS_PETSC(VecMDot(lin_.g[actuators_[a].constraint], n, response_.data(), wdots.data()));
    for (int b = 0; b < n; ++b) growth(a, b) = wdots[b];
  }
}

Eigen::VectorXd InverseController::solve_actuation(const Eigen::MatrixXd& W,
                                                   const Eigen::VectorXd& delta,
                                                   const Eigen::MatrixXd& growth,
                                                   ControlStepReport& report) {
  const int n = num_actuators();
  Eigen::MatrixXd H = W.transpose() * W;
  const double scale = std::max(H.trace() / std::max(n, 1), 1e-300);
  H += config_.control->regularization * scale * Eigen::MatrixXd::Identity(n, n);
  const Eigen::VectorXd f = W.transpose() * delta;
  std::vector<Eigen::RowVectorXd> rows;
  std::vector<double> rhs;
  std::vector<int> owner;  // actuator of each constraint row
  auto bound = [&](const Eigen::RowVectorXd& row, double lower, int a) {
    if (std::isfinite(lower) && lower > -1e299) {
      rows.push_back(row);
      rhs.push_back(lower);
      owner.push_back(a);
    }
  };
  if (static_cast<int>(change_origin_.size()) != n) {
    change_origin_.resize(n);
    for (int a = 0; a < n; ++a)
      change_origin_[a] = constraints_[actuators_[a].constraint].multiplier();
  }
  for (int a = 0; a < n; ++a) {
    const auto& b = actuators_[a].config;
    const double lambda = constraints_[actuators_[a].constraint].multiplier();
    const double origin = change_origin_[a];  // the change per step counts from there
    PetscScalar free_growth = 0;              // the free step's volume change (linear)
    HS_PETSC(VecDot(lin_.g[actuators_[a].constraint], free_step_, &free_growth));
    const double grown =
        constraints_[actuators_[a].constraint].measure() + free_growth - actuators_[a].rest_measure;
    Eigen::RowVectorXd unit = Eigen::RowVectorXd::Zero(n);
    unit(a) = 1;
    bound(unit, b.min_multiplier - lambda, a);
    bound(-unit, lambda - b.max_multiplier, a);
    bound(unit, origin - b.max_multiplier_step - lambda, a);
    bound(-unit, lambda - origin - b.max_multiplier_step, a);
    bound(growth.row(a), b.min_measure_change - grown, a);
    bound(-growth.row(a), grown - b.max_measure_change, a);
  }
  Eigen::MatrixXd A(rows.size(), n);
  Eigen::VectorXd bvec(rows.size());
  for (size_t r = 0; r < rows.size(); ++r) {
    A.row(r) = rows[r];
    bvec(r) = rhs[r];
  }
  QpResult qp = solve_qp(H, f, A, bvec);
  report.qp_solved = qp.solved;
  report.qp_status = qp.status;
  Eigen::VectorXd dl = Eigen::VectorXd::Zero(n);
  if (qp.solved) {
    dl = qp.x;
    report.kkt_residual = qp.kkt_residual;
  }
  report.saturated.assign(n, false);
  for (int r : qp.active) report.saturated[owner[r]] = true;
  return dl;
}

}  // namespace hs
