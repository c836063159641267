// The inverse controller of the paper (Section II, Steps 1-3) on hydrosoft's cavities:
//   1. free: Newton at the current actuation (every actuator's pressure held) -> x_free
//      (control.free_solve: one_step takes the first Newton step of 2's factorization);
//   2. compliance: at x_free, one factorization of K, and the response du_k of the whole
//      system to a unit pressure change of actuator k (the bordered elimination of
//      solvers/bordered_newton.hpp: sealed chambers keep their gas or volume, the liquid's
//      weight follows the volume, so a hydraulic actuator acts through the unified
//      constraint of Section IV, made exact); W = J_e [du_1 .. du_n];
//   3. a dense QP for the pressure changes dl: min 1/2 |W dl + delta_free|^2 + eps/2 |dl|^2
//      (weights and directions of the effectors inside W), under the actuators' bounds
//      (pressure, volume growth since rest, change per step);
//   4. correction: x = x_free + sum_k du_k dl_k (the paper's equation 4), optionally
//      finished by Newton at the new actuation.
// docs/control.md derives it and says how each step is timed.
#pragma once

#include <petscksp.h>

#include <Eigen/Dense>
#include <memory>
#include <nlohmann/json.hpp>
#include <vector>

#include "solvers/bordered_newton.hpp"
#include "solvers/bordered_system.hpp"
#include "solvers/checkpoint.hpp"
#include "solvers/constraints/constraint_set.hpp"
#include "solvers/control/background_factorizations.hpp"
#include "solvers/control/contact_qp.hpp"
#include "solvers/effectors.hpp"
#include "solvers/solver_options.hpp"

namespace hs {

struct ControlStepReport {
  std::vector<double> actuation;  // pressures of the actuators after the step (Pa)
  std::vector<bool> saturated;    // per actuator: a bound of it is active in the QP
  std::vector<double> reached;    // 3 per effector after the step
  double error = 0;               // |x_e - target| over the targeted effectors (m)
  double kkt_residual = 0;        // of the QP solution
  bool qp_solved = true;
  std::string qp_status;
  // Milliseconds, slowest rank: assembly (all of the step's), fluid weight (all), the free
  // Newton solve's own linear algebra, the factorization at x_free, compliance (the solves
  // and dots of the responses), QP, correction (with Newton finishing: its solve), the step.
  double assembly_ms = 0, fluid_weight_ms = 0, free_solve_ms = 0, factorization_ms = 0,
         compliance_ms = 0, qp_ms = 0, correction_ms = 0, total_ms = 0;
  // The parts of total_ms by their names in summary.json's step_time_ms.split_median.
  std::vector<std::pair<std::string, double>> parts() const {
    return {{"assembly", assembly_ms},     {"fluid_weight", fluid_weight_ms},
            {"free_solve", free_solve_ms}, {"factorization", factorization_ms},
            {"compliance", compliance_ms}, {"qp", qp_ms},
            {"correction", correction_ms}};
  }
  int newton_iterations = 0;
  // control.factor_threads > 0: how many steps old the state of the factorization that
  // preconditioned this step's correction was (0: factored in line at this step's state),
  // the correction's GMRES iterations over all right-hand sides, and a background
  // factorization that failed (the step then factored in line).
  int staleness = 0;
  int correction_iterations = 0;
  std::string background_failure;
  // The free configuration could not reach the actuation of the last correction (a limit
  // point of the pressure: no equilibrium there) and stayed at the last one reached.
  bool limit_point = false;
  // one_step: the passes taken again with a fresh factorization (control.one_step_tolerance),
  // and how far the last free step from a correction moved the targeted effectors (m), and
  // changed the targeted contact forces (N): a lower bound of the answer's distance from its
  // equilibrium (docs/control.md).
  int refinements = 0;
  double free_step_m = 0, free_step_N = 0;
  // Negative pivots of the in-line L D L^T factorization the step used (MUMPS; -1 when not
  // known: another solver, or no in-line factorization this step), and what the step did
  // instead of trusting an indefinite tangent (empty when nothing).
  int negative_pivots = -1;
  std::string fallback;
  // control.contact_forces qp: the candidates, the nodes touching, the active sets tried, the
  // smallest linearised gap and force and the largest |force x gap| (ContactActuation).
  nlohmann::json contact_qp;
  // A reduced model's answer (solvers/reduced/reduced_controller.hpp): whether the actuation
  // lies in its training envelope, and its error estimate; null for the full model.
  nlohmann::json reduced;
};

class InverseController {
 public:
  // Collective. Checks the actuators (a pneumatic or hydraulic cavity each) and their bounds.
  InverseController(const Config& config, Problem& problem, ConstraintSet& constraints,
                    BorderedNewton& newton, Effectors& effectors);
  ~InverseController();
  InverseController(const InverseController&) = delete;
  InverseController& operator=(const InverseController&) = delete;

  KSP ksp() const { return ksp_; }  // its own, with the options of prefix hs_control_
  // The background factorizations (control.factor_threads > 0), else null.
  BackgroundFactorizations* background() { return background_.get(); }
  int num_actuators() const { return static_cast<int>(actuators_.size()); }
  // Records the rest state's volumes (volume growth is counted from there).
  void set_rest(Vec u);
  // One control step towards `targets` from configuration u (updated in place).
  ControlStepReport step(Vec u, const std::vector<ControlTarget>& targets);
  // Equilibrium at the current actuation (the next step's free configuration, computed now):
  // the position the effectors really reach, where a step's own report gives the linear
  // prediction of its correction. Updates the report's reached, actuation, limit_point.
  void settle(Vec u, ControlStepReport& report);
  // The equilibrium at the current actuation, computed on a copy of u (u, the pressures and
  // the controller's state are left as they were): the position a one_step controller's
  // prediction stands for. Throws SolveError when Newton does not converge.
  std::vector<double> equilibrium_positions(Vec u);

  // After a step that failed (SolveError) and u and the constraints were put back to the
  // last answered state: the kept factorization and the retake flags are dropped, so that
  // the next step starts afresh there.
  void recover();

  // Checkpoints at a target-set boundary (docs/control.md, "Checkpoints and restarts"): what
  // the controller keeps between steps, as JSON scalars and named vectors (valid until the
  // next step), and the same put back from a checkpoint. resume() is collective; with a
  // factorization kept across steps (refactor_every > 1) it factors again the tangent of the
  // state that factorization was made at.
  nlohmann::json checkpoint_state() const;
  NamedVecs checkpoint_fields() const;
  void resume(const nlohmann::json& state, const Restart& restart);

 private:
  struct Actuator {
    ActuatorConfig config;
    int constraint = -1;
    double rest_measure = 0;
  };

  // The wall-clock times of one step's parts and the assembly before it (the report's ms).
  struct StepClock {
    double start = 0, free = 0, factor = 0, compliance = 0, qp = 0, correction = 0;
    double assembly0 = 0, fluid0 = 0, free_overhead = 0;
  };

  NewtonResult solve_free(Vec u, ControlStepReport& report);
  // Step 1 (the clock started): the actuators' multipliers held, and the free configuration
  // converged unless the step is one_step's.
  void converge_free(Vec u, bool one_step, ControlStepReport& report, StepClock& clock);
  ControlStepReport retake(Vec u, const std::vector<ControlTarget>& targets, double started,
                           const std::string& why);
  // The residual R_ (and the controls) at the start of step 2, gone back to the last step's
  // start when a correction with a kept factorization overshot (stale_failed); its norm.
  double start_residual(Vec u, bool one_step, std::vector<double>& controls, bool& stale_failed);
  // Step 2: linearises and factors when due (with the responses), else solves R_ with the kept
  // factorization; whether the factorization is of this step's state.
  bool factor_if_due(Vec u, bool one_step, bool stale_failed, double r_norm,
                     ControlStepReport& report, StepClock& clock);
  bool correct_in_background(bool stale_failed, ControlStepReport& report, StepClock& clock);
  // one_step: a free step from the step's correction (a residual, one solve with the step's
  // solver), and the step taken again from the correction with a fresh factorization while
  // that free step moves the targeted effectors by more than control.one_step_tolerance (or
  // inverts an element).
  void refine(Vec u, const std::vector<ControlTarget>& targets, ControlStepReport& report);
  // The negative pivots of ksp_'s factorization (MUMPS L D L^T), -1 when not known.
  int negative_pivots() const;
  void take_free_step(Vec u, const std::vector<double>& controls);
  // W (the weighted compliance of the targeted effectors), delta (their weighted distance
  // to the targets) and each actuator's volume growth per unit of each actuation.
  void compliance_rows(Vec u, const std::vector<ControlTarget>& targets, Eigen::MatrixXd& W,
                       Eigen::VectorXd& delta, Eigen::MatrixXd& growth);
  // Step 3: the pressure changes dl from the QP; the report's QP fields and saturation.
  Eigen::VectorXd solve_actuation(Vec u, const std::vector<ControlTarget>& targets,
                                  const Eigen::MatrixXd& W, const Eigen::VectorXd& delta,
                                  const Eigen::MatrixXd& growth, ControlStepReport& report);
  // Step 4: u and the multipliers corrected by dl (and Newton at the new actuation).
  void correct(Vec u, const Eigen::VectorXd& dl, ControlStepReport& report);
  // A linearised step (the free step and the correction) can carry a contact node into an
  // obstacle, where the barrier is infinite and no later residual can be evaluated: such a
  // step is shortened as Newton's are (Problem::contact_step_limit: a tenth of each gap kept),
  // the displacements and the multipliers together, from where it linearised, and the answer
  // says so in `fallback`.
  void keep_outside_obstacles(Vec u, ControlStepReport& report);
  void finish_report(Vec u, const std::vector<ControlTarget>& targets, const StepClock& clock,
                     ControlStepReport& report);
  // Solves the step's right-hand sides with ksp (adding its iterations to *iterations) and
  // forms the responses; false when a solve failed.
  bool factor_responses(KSP ksp, int* iterations = nullptr);

  const Config& config_;
  Problem& problem_;
  ConstraintSet& constraints_;
  BorderedNewton& newton_;
  Effectors& effectors_;
  std::vector<Actuator> actuators_;
  SolverOptions options_;  // prefix hs_control_; before the KSP: it outlives it
  KspHandle ksp_;
  std::unique_ptr<BackgroundFactorizations> background_;  // control.factor_threads > 0
  std::unique_ptr<ContactQp> contact_qp_;                 // control.contact_forces: qp
  Eigen::VectorXd contact_dforce_;  // its force changes of the step (correct() adds them)
  int step_count_ = 0;              // steps begun, retakes included
  MatHandle J_;
  VecArray response_;  // per actuator
  ConstraintLinearization lin_;
  VecHandle R_, free_step_;  // residual, the free step
  VecHandle contact_move_;   // a step's move from its start (keep_outside_obstacles)
  // The elimination and the responses of the last factorization (kept for
  // control.refactor_every steps).
  BorderedSystem system_;
  std::vector<bool> actuated_;
  Eigen::MatrixXd zeta_;
  bool factored_ = false;
  int pattern_version_ = 0;  // self-contact's tangent pattern at the last factorization
  KSP step_ksp_ = nullptr;   // the solver of this step's responses (in line or the correction)
  // Each actuator's actuation before the step's first QP: the per-step change bound counts
  // from there, refinements included.
  std::vector<double> change_origin_;
  // The last one_step correction inverted an element: take the step again with a fresh
  // factorization, or (if it had one) with the free configuration converged.
  bool force_refactor_ = false, retake_converged_ = false;
  bool shortened_at_obstacle_ = false;  // by the last keep_outside_obstacles
  int steps_since_factorization_ = 0;
  double residual_at_factorization_ = 0;  // |R| at the start of that step
  VecHandle step_start_;  // u and pressures where the last step linearised (its start)
  std::vector<double> step_start_pressures_;
  VecHandle last_free_;  // the last free equilibrium and its pressures
  std::vector<double> last_pressures_;
  DofMap::Moves last_moves_;  // and its boundary groups' translations (a target set's `move`)
  // refactor_every > 1 (in line): the configuration and the constraints' states that the
  // kept factorization was made at, for a restart to make it again.
  bool keeps_factorization() const;
  VecHandle factored_at_;
  nlohmann::json factored_constraints_;
};

}  // namespace hs
