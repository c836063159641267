// Steps 2 and 3 of the controller's step (solvers/inverse_controller.hpp): the compliance W of
// the targeted effectors and the volume growth of each actuator from the responses, and the
// dense QP for the pressure changes under the actuators' bounds.
#include <algorithm>
#include <cmath>

#include "control/actuation_qp.hpp"
#include "control/contact_actuation_qp.hpp"
#include "solvers/inverse_controller.hpp"

namespace hs {

// Effector rows (weighted, controlled directions of the targeted effectors) and volumes.
void InverseController::compliance_rows(Vec u, const std::vector<ControlTarget>& targets,
                                        Eigen::MatrixXd& W, Eigen::VectorXd& delta,
                                        Eigen::MatrixXd& growth) {
  const int n = num_actuators();
  if (!contact_qp_)
    effectors_.linearize(u);  // the contact forces' rows at x_free (qp: ContactQp's)
  const std::vector<double> x_free = effectors_.positions(u);
  std::vector<double> rows_delta;
  std::vector<std::vector<double>> rows_W;
  std::vector<PetscScalar> wdots(n);
  for (const auto& t : targets) {
    const int e = effectors_.index(t.effector);
    const auto& ec = effectors_.config(e);
    // A force effector out of contact closes its gap: its rows are a unit spring across the
    // nearest node's gap, scaled so that closing the gap gives the force asked for (the real
    // rows take over once it touches: docs/control.md).
    double scale = ec.weight;
    if (contact_qp_ && effectors_.is_force(e))
      scale = 0;  // its forces are the QP's unknowns (ContactQp gives its rows)
    else if (effectors_.is_force(e) && effectors_.approach_gap(e) > 0) {
      double asked2 = 0;
      for (int d = 0; d < 3; ++d)
        if (ec.directions[d]) asked2 += t.position[d] * t.position[d];
      scale *= std::sqrt(asked2) / effectors_.approach_gap(e);
    }
    for (int d = 0; d < 3; ++d) {
      if (!ec.directions[d]) continue;
      HS_PETSC(VecMDot(effectors_.row(e, d), n, response_.data(), wdots.data()));
      std::vector<double> r(n);
      for (int a = 0; a < n; ++a) r[a] = scale * wdots[a];
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

Eigen::VectorXd InverseController::solve_actuation(Vec u, const std::vector<ControlTarget>& targets,
                                                   const Eigen::MatrixXd& W,
                                                   const Eigen::VectorXd& delta,
                                                   const Eigen::MatrixXd& growth,
                                                   ControlStepReport& report) {
  const int n = num_actuators();
  if (static_cast<int>(change_origin_.size()) != n) {
    change_origin_.resize(n);
    for (int a = 0; a < n; ++a)
      change_origin_[a] = constraints_[actuators_[a].constraint].multiplier();
  }
  std::vector<ActuatorConfig> bounds;
  std::vector<ActuatorPosition> at(n);
  for (int a = 0; a < n; ++a) {
    const Constraint& c = constraints_[actuators_[a].constraint];
    PetscScalar free_growth = 0;  // the free step's volume change (linear)
    HS_PETSC(VecDot(lin_.g[actuators_[a].constraint], free_step_, &free_growth));
    bounds.push_back(actuators_[a].config);
    at[a] = {c.multiplier(), change_origin_[a],
             c.measure() + free_growth - actuators_[a].rest_measure};
  }
  ActuationChange change;
  if (contact_qp_) {
    std::vector<int> constraint_of;
    for (const auto& a : actuators_) constraint_of.push_back(a.constraint);
    ContactBlocks blocks = contact_qp_->linearize(u, step_ksp_, system_, lin_, actuated_,
                                                  {response_.data(), response_.data() + n},
                                                  constraint_of, targets, W, delta);
    blocks.growth_a = growth;
    const ContactActuation answer =
        solve_contact_actuation_qp(blocks, bounds, at, config_.control->regularization);
    change = answer.change;
    contact_dforce_ = answer.dforce;
    report.contact_qp = {{"candidates", contact_qp_->num_candidates()},
                         {"touching", answer.touching},
                         {"passes", answer.passes},
                         {"cycled", answer.cycled},
                         {"least_gap_m", answer.least_gap},
                         {"least_force_N", answer.least_force},
                         {"complementarity_Nm", answer.worst_product}};
  } else {
    change = solve_actuation_qp(W, delta, growth, bounds, at, config_.control->regularization);
  }
  report.qp_solved = change.solved;
  report.qp_status = change.status;
  report.kkt_residual = change.kkt_residual;
  report.saturated = change.saturated;
  return change.dl;
}

}  // namespace hs
