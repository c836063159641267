// The inverse controller on a reduced-order model (docs/reduced_models.md): the steps of the
// full model's controller (solvers/inverse_controller.hpp) in the model's reduced space, where
// a factorization is of a k x k matrix. Each step is Newton's method on the equilibrium and
// the QP together, within the step's bounds:
//   1. the equations linearized at (q, lambda): r + K dq - G dl = 0 (the actuators' unit
//      forces G);
//   2. Newton's step at fixed actuation -K^-1 r, the compliance dq/dlambda = K^-1 G, the
//      effectors' rows W and the volume growth;
//   3. the QP of the full model (control/actuation_qp.hpp) for the actuation change dl;
//   4. q += -K^-1 r + K^-1 G dl, lambda += dl,
// until r balances and dl vanishes, so that every answer is the reduced model's equilibrium.
// The whole field Phi q is placed in u after the step (outside its time), for the output.
#pragma once

#include <petscvec.h>

#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

#include "control/actuation_qp.hpp"
#include "reduction/model_file.hpp"
#include "solvers/effectors.hpp"
#include "solvers/inverse_controller.hpp"
#include "solvers/reduced/error_indicator.hpp"
#include "solvers/reduced/reduced_system.hpp"

namespace hs {

class ReducedController {
 public:
  // Reads and checks the deck's control.reduced_model (InputError naming the file).
  ReducedController(const Config& config, Problem& problem, ConstraintSet& constraints,
                    Effectors& effectors);

  // The rest state: its reduced coordinates (u projected, then the reduced equilibrium at the
  // rest actuation) and the actuators' rest measures.
  void set_rest(Vec u);
  ControlStepReport step(Vec u, const std::vector<ControlTarget>& targets);
  // After a step that failed and u and the constraints were put back: q from u again.
  void recover(Vec u);
  // summary.json's `reduced_model`: the file, its sizes, its training errors.
  nlohmann::json summary() const;

 private:
  // An answer's `reduced`: whether its actuation lies in the training envelope, and its
  // stated error there: the residual indicator times the training's calibration
  // (error_indicator.hpp), or the held-back samples' largest error. u: the answer's field.
  nlohmann::json error_statement(Vec u, bool inside);
  // The effectors' positions at reduced coordinates q (3 each).
  Eigen::VectorXd effector_positions(const Eigen::VectorXd& q) const;
  // The QP's rows: W, the targeted directions' weighted response to the actuation (through
  // dq = dq/dlambda), and delta, their weighted distance from the targets at the reduced
  // coordinates q.
  void target_rows(const std::vector<ControlTarget>& targets, const Eigen::VectorXd& q,
                   const Eigen::MatrixXd& dq, Eigen::MatrixXd& W, Eigen::VectorXd& delta) const;
  // The step q += dq, lambda += dl; L then the equations linearized there. Where it lands
  // with a residual above `far` times the forces (and above the last one), Newton solves the
  // equilibrium at that actuation first; dl is halved
  // while none is found. False (q and the actuation put back) when no length serves: a limit
  // point of the pressure.
  bool move(Vec u, const Eigen::VectorXd& dq, const Eigen::VectorXd& dl, ReducedLinearization& L,
            ControlStepReport& report, double far);
  // The weighted distance of effector positions x (3 per effector) from the targets.
  double target_distance(const Eigen::VectorXd& x, const std::vector<ControlTarget>& targets) const;
  // The training sample whose effectors lie nearest the targets (within the step's change of
  // the actuation), when it is less than half as far from them as the current state; -1 for
  // none. Only where the targets fix the actuation (at least as many targeted directions as
  // actuators), so that the QP's fixed point, and the answer, do not depend on the start.
  Eigen::Index training_start(const std::vector<ControlTarget>& targets,
                              const std::vector<ActuatorPosition>& at) const;
  // Where a step's Newton starts, linearized: that training sample (q and the actuation
  // there), or where the last step ended (its last linearization, kept).
  ReducedLinearization start(Vec u, const std::vector<ControlTarget>& targets,
                             const std::vector<ActuatorPosition>& at);
  const Config& config_;
  ConstraintSet& constraints_;
  Effectors& effectors_;
  std::string path_;
  ReducedModel model_;
  std::unique_ptr<ReducedSystem> system_;
  std::unique_ptr<ResidualErrorIndicator> indicator_;  // null with control.error_indicator off
  double indicator_s_ = 0;
  std::vector<int> actuators_;  // constraint of each actuator
  std::vector<double> rest_measure_;
  Eigen::VectorXd q_;
  Eigen::MatrixXd effector_rows_;             // 3 per effector x k: x_e = reference + rows q
  std::vector<double> reference_;             // the effectors' reference positions
  Eigen::MatrixXd training_positions_;        // the effectors' at each training sample (columns)
  std::optional<ReducedLinearization> kept_;  // at q_ and the actuation, the last step's end
  int steps_ = 0, outside_ = 0;               // steps taken, answers outside the training envelope
};

}  // namespace hs
