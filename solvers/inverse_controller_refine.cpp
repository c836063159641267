// The one_step controller's guards (docs/control.md, "The real-time step"): the refinement of a
// step's correction with the step's own solver, the inertia of its factorization, and the
// reset after a step that failed.
#include <petscksp.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "common/error.hpp"
#include "solvers/inverse_controller.hpp"
#include "solvers/mixed_factor.hpp"

namespace hs {
namespace {

// Fresh passes converge as Newton does: two met the equilibrium to round-off on the finger's
// sweep; more than four means the step is far from its equilibrium (free_step_m says so).
constexpr int kMaxRefinements = 4;

}  // namespace

// One linearisation predicts the motion of a pressure change with the compliance at the start
// of the step; on a body that softens as it deforms (near a limit point of the pressure, or a
// PneuNet bending far) the equilibrium at the new pressure lies beyond the prediction, and the
// next step, finding its free configuration past the target, took the pressure back: the
// actuation went the wrong way on monotone targets (docs/control.md). So the step ends with a
// free step from its correction (one residual, one solve with the step's factorization): the
// answer is that free configuration. While the free step moved the targeted effectors by more
// than the tolerance (free_step_m; made with the factorization of before the pressure change it
// underestimates the distance to equilibrium, 3-10 times on the fingers), the step is taken
// again from the correction with a fresh factorization (chord steps with the step's old one did
// not converge after a jump of 5 kPa on the hydraulic finger), its pressure change still counted
// from the step's start. From the correction, not from the free step's end: that chord step,
// made from a residual whose nodal pressures carry the linear step's volume error times k,
// leaves a nearly incompressible body where a fresh tangent has negative pivots (3 to 11 on
// the silicone finger, none at the correction; docs/control.md, "At silicone's nu"); on the
// coarse finger near its limit point, the same (three indefinite tangents met there). Beside
// obstacles the chord step's end stays the start.
void InverseController::refine(Vec u, const std::vector<ControlTarget>& targets,
                               ControlStepReport& report) {
  const double tolerance = config_.control->one_step_tolerance;
  if (tolerance <= 0 || !step_ksp_) return;
  VecHandle before;
  HS_PETSC(VecDuplicate(u, before.out()));
  std::vector<double> at_answer;  // the correction's pressures
  const auto back_to_correction = [&] {
    HS_PETSC(VecCopy(before, u));
    constraints_.set_multipliers(at_answer);
    for (const auto& a : actuators_) constraints_[a.constraint].hold_multiplier();
  };
  // The answer: the equilibrium at the held pressures, converged by Newton from u.
  const auto equilibrium_answer = [&](const std::string& why) {
    for (const auto& a : actuators_) constraints_[a.constraint].hold_multiplier();
    const NewtonResult r = solve_free(u, report);
    report.fallback += std::string(report.fallback.empty() ? "" : "; ") + why +
                       ": the answer is the equilibrium at its actuation, converged by Newton";
    if (!r.converged)
      throw SolveError("control step: no equilibrium at the actuation after " + why + " (" +
                       r.reason + ")");
    report.free_step_m = report.free_step_N = 0;
  };
  for (int pass = 0;; ++pass) {
    std::vector<double> controls;
    problem_.apply_dirichlet(u, 1.0);
    if (!constraints_.residual(u, 1.0, R_, controls)) break;  // checked: cannot be inverted
    system_.solve_residual(step_ksp_, R_);
    const std::vector<double> x0 = effectors_.positions(u);
    at_answer = constraints_.multipliers();
    HS_PETSC(VecCopy(u, before));
    take_free_step(u, controls);
    const bool inverted = !problem_.orientation_preserved(u);
    // A free step into an obstacle (where the barrier is infinite) is not taken either.
    const bool enters = !inverted && problem_.contact_step_limit(before, free_step_, 1.0) < 1;
    // A chord step that inverts an element says as little about the distance to equilibrium as
    // one that moves far: a fresh pass follows, while there is one (the PneuNet of silicone on
    // P2 F-bar: its chord steps inverted an element at 9 of 13 lines). Not beside obstacles,
    // whose barrier a fresh pass from there met in its own chord step (the finger on the ball
    // was answered 0.8 mm from equilibrium; docs/contact.md).
    const bool again = inverted && !problem_.has_contact() && pass < kMaxRefinements;
    // Beside obstacles such a correction can lie far from its equilibrium, where the contact
    // it linearised opened or closed: on the silicone gripper of input/gripper_grasp.yaml one
    // pressed the ball with 0.27 N where its equilibrium gave 0.012 N; a finger landing on a
    // ball from above was answered 6.6 mm from its equilibrium. Its equilibrium is the answer.
    if (problem_.has_contact() && (enters || inverted)) {
      back_to_correction();
      equilibrium_answer(
          std::string("the free step after the correction ") +
          (inverted ? "inverted an element" : "carried a node into an obstacle or onto a surface"));
      break;
    }
    if (inverted && !again) {  // the answer: the correction
      back_to_correction();
      report.fallback += std::string(report.fallback.empty() ? "" : "; ") +
                         "the free step after the correction inverted an element: not taken";
      break;
    }
    if (!inverted) {
      for (int c = 0; c < constraints_.size(); ++c) constraints_[c].update_measure(u);
      const std::vector<double> x1 = effectors_.positions(u);
      double moved2[2] = {0, 0};  // positions (m), contact forces (N)
      for (const auto& t : targets) {
        const int e = effectors_.index(t.effector);
        for (int d = 0; d < 3; ++d)
          if (effectors_.config(e).directions[d])
            moved2[effectors_.is_force(e)] += std::pow(x1[3 * e + d] - x0[3 * e + d], 2);
      }
      report.free_step_m = std::sqrt(moved2[0]);
      report.free_step_N = std::sqrt(moved2[1]);
      if (std::max(report.free_step_m, report.free_step_N) <= tolerance || pass == kMaxRefinements)
        break;
    }
    // Again, freshly linearised: from the correction, or beside obstacles from the chord step's
    // end (above: from the correction, the finger pressing the ball was answered 0.8 mm from
    // equilibrium where the chord step's end gave 0.15 mm; the barrier is what that step
    // approached). Not on a nodal-pressure body, whose chord step's end is where its tangent
    // turns indefinite (above): the silicone gripper of input/gripper_grasp.yaml met 5-49
    // negative pivots there at every line, and none from the correction.
    ++report.refinements;
    if (problem_.has_contact() && !problem_.has_nodal_pressure()) {
      HS_PETSC(VecCopy(u, before));
    } else {
      back_to_correction();
      for (int c = 0; c < constraints_.size(); ++c) constraints_[c].update_measure(u);
    }
    const std::vector<double> pressures = constraints_.multipliers();
    StepClock clock;
    bool stale_failed = false;
    force_refactor_ = true;
    const double r_norm = start_residual(u, true, controls, stale_failed);
    ControlStepReport pass_report;
    factor_if_due(u, true, false, r_norm, pass_report, clock);
    force_refactor_ = false;
    if (!pass_report.background_failure.empty())  // found by this pass's poll
      report.background_failure = pass_report.background_failure;
    if (pass_report.negative_pivots > 0) {  // not trusted: Newton at the held pressures
      equilibrium_answer("a refinement met a tangent with " +
                         std::to_string(pass_report.negative_pivots) + " negative pivots");
      break;
    }
    take_free_step(u, controls);
    Eigen::MatrixXd W, growth;
    Eigen::VectorXd delta;
    compliance_rows(u, targets, W, delta, growth);
    const Eigen::VectorXd dl = solve_actuation(u, targets, W, delta, growth, report);
    correct(u, dl, report);
    if (shortened_at_obstacle_) {  // linearisations no longer serve: Newton at the pressures
      for (const auto& a : actuators_) constraints_[a.constraint].hold_multiplier();
      const NewtonResult r = solve_free(u, report);
      if (!r.converged)
        throw SolveError(
            "control step: no equilibrium at the actuation after a step shortened "
            "at an obstacle (" +
            r.reason + ")");
      report.fallback += "; the answer is the equilibrium at its actuation, converged by Newton";
      report.free_step_m = report.free_step_N = 0;
      break;
    }
    if (!problem_.orientation_preserved(u)) {
      HS_PETSC(VecCopy(before, u));
      constraints_.set_multipliers(pressures);
      for (const auto& a : actuators_) constraints_[a.constraint].hold_multiplier();
      for (int c = 0; c < constraints_.size(); ++c) constraints_[c].update_measure(u);
      report.fallback += std::string(report.fallback.empty() ? "" : "; ") +
                         "a refinement inverted an element: the answer before it was kept";
      break;
    }
  }
}

int InverseController::negative_pivots() const {
  PC pc;
  HS_PETSC(KSPGetPC(ksp_, &pc));
  if (const int mixed = mixed_factor_negative_pivots(pc); mixed >= 0) return mixed;
  PetscBool cholesky = PETSC_FALSE;
  HS_PETSC(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), PCCHOLESKY, &cholesky));
  if (!cholesky) return -1;
  Mat F;
  HS_PETSC(PCFactorGetMatrix(pc, &F));
  MatSolverType type = nullptr;
  HS_PETSC(MatFactorGetSolverType(F, &type));
  if (!type || std::strcmp(type, MATSOLVERMUMPS) != 0) return -1;
  PetscInt negative = 0;
  HS_PETSC(MatMumpsGetInfog(F, 12, &negative));  // the same on every rank
  return static_cast<int>(negative);
}

void InverseController::recover() {
  factored_ = false;
  retake_converged_ = false;
  force_refactor_ = true;  // in line, whatever background factorization there is
  steps_since_factorization_ = 0;
  residual_at_factorization_ = 0;
  change_origin_.clear();
}

}  // namespace hs
