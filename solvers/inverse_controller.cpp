#include "solvers/inverse_controller.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/error.hpp"
#include "solvers/multi_solve.hpp"
#include "solvers/stepping.hpp"

namespace hs {
namespace {

// The background mode's correction: GMRES's relative residual for each right-hand side
// (-hs_control_correction_ksp_rtol overrides it).
constexpr double kCorrectionRtol = 1e-5;

double max_over_ranks(double x, MPI_Comm comm) {
  MPI_Allreduce(MPI_IN_PLACE, &x, 1, MPI_DOUBLE, MPI_MAX, comm);
  return x;
}

}  // namespace

InverseController::InverseController(const Config& config, Problem& problem,
                                     ConstraintSet& constraints, BorderedNewton& newton,
                                     Effectors& effectors)
    : config_(config),
      problem_(problem),
      constraints_(constraints),
      newton_(newton),
      effectors_(effectors),
      options_(kControlPrefix, config.solver,
               preset_options(config.solver.preset, newton.tangent()),
               SolverOptions::Reach::every_object),
      system_(problem, constraints, BorderedSystem::Order::g_then_q) {
  for (const auto& a : config.control->actuators) {
    Actuator act;
    act.config = a;
    act.constraint = constraints.find(a.constraint);
    const std::string where = config.deck_path + ": control.actuators '" + a.constraint + "'";
    if (act.constraint < 0) throw InputError(where + ": no cavity or cable of that name");
    if (!constraints[act.constraint].actuated())
      throw InputError(where + ": a " + constraints[act.constraint].kind() +
                       " chamber is not actuated (it enters fixed)");
    actuators_.push_back(act);
  }
  {
    const OptionsScope scope(options_.database());  // the matrix's options too (-mat_view)
    J_ = MatHandle(problem.create_matrix(options_.factors_mixed()));
    HS_PETSC(KSPCreate(problem.comm(), ksp_.out()));
    options_.attach(reinterpret_cast<PetscObject>(ksp_.get()));
    HS_PETSC(KSPSetOptionsPrefix(ksp_, kControlPrefix));
    HS_PETSC(KSPSetFromOptions(ksp_));
  }
  if (config.control->factor_threads > 0 && config.control->free_solve == FreeSolve::one_step)
    background_ = std::make_unique<BackgroundFactorizations>(
        problem.comm(), config.control->factor_threads, ksp_, kCorrectionRtol, config.solver);
  for (size_t a = 0; a < actuators_.size(); ++a) response_.push_back(problem.create_vector());
  if (config.control->contact_forces == ContactForces::qp)
    contact_qp_ = std::make_unique<ContactQp>(problem, effectors);
  R_ = VecHandle(problem.create_vector());
  free_step_ = VecHandle(problem.create_vector());
}

InverseController::~InverseController() {
  background_.reset();  // it holds ksp_ (not owning it): it goes first
}

// The bordered elimination at the current linearization (solvers/bordered_system.hpp), with
// the actuators' rows taking their input and the other cavities keeping their control; and
// the response of the whole system to each actuator.
bool InverseController::factor_responses(KSP ksp, int* iterations) {
  const int m = constraints_.size(), n = num_actuators();
  if (!system_.solve(ksp, R_, lin_, iterations)) return false;
  actuated_.assign(m, false);
  Eigen::MatrixXd inputs = Eigen::MatrixXd::Zero(system_.size(), n);
  for (int a = 0; a < n; ++a) {
    actuated_[actuators_[a].constraint] = true;
    inputs(actuators_[a].constraint, a) = 1;
  }
  system_.factor_dense(lin_, actuated_);
  zeta_ = system_.solve_dense(inputs);  // k x n
  for (int a = 0; a < n; ++a) system_.response(zeta_.col(a), response_[a]);
  return true;
}

ControlStepReport InverseController::step(Vec u, const std::vector<ControlTarget>& targets) {
  ControlStepReport report;
  StepClock clock;
  // Step 1: the free configuration at the current actuation, converged by Newton; in the
  // one_step mode it is the first Newton step of step 2's linearisation instead.
  const bool one_step = config_.control->free_solve == FreeSolve::one_step && !retake_converged_;
  converge_free(u, one_step, report, clock);

  // Step 2: one linearisation, one factorization, and the response to each actuator; the
  // free step from there.
  std::vector<double> controls;
  bool stale_failed = false;
  change_origin_.clear();
  const double r_norm = start_residual(u, one_step, controls, stale_failed);
  const bool fresh = factor_if_due(u, one_step, stale_failed, r_norm, report, clock);
  // An indefinite tangent (negative pivots of L D L^T) is not trusted for a step from a
  // configuration that is not an equilibrium: its free step may climb instead of descend.
  // The step is taken again with the free configuration converged by Newton (which walks the
  // pressures and stops at a limit point), and the answer says so.
  if (one_step && report.negative_pivots > 0) {
    retake_converged_ = true;
    return retake(u, targets, clock.start,
                  "the tangent had " + std::to_string(report.negative_pivots) +
                      " negative pivots (not positive definite): the free configuration was "
                      "converged by Newton");
  }
  if (!one_step && report.negative_pivots > 0)
    report.fallback = "the tangent at the free equilibrium has " +
                      std::to_string(report.negative_pivots) +
                      " negative pivots (an unstable equilibrium under held pressures)";
  take_free_step(u, controls);
  Eigen::MatrixXd W, growth;
  Eigen::VectorXd delta;
  compliance_rows(u, targets, W, delta, growth);
  clock.qp = MPI_Wtime();

  // Step 3: the QP for the pressure changes.
  const Eigen::VectorXd dl = solve_actuation(u, targets, W, delta, growth, report);
  clock.correction = MPI_Wtime();

  // Step 4: correction x = x_free + sum_a du_a dl_a, and the pressures of every cavity.
  correct(u, dl, report);
  // A one-linearisation correction that inverts an element is taken again at once, so that
  // no step hands out (or writes) an inverted body: with a fresh factorization if it used a
  // kept one, else with the free configuration converged by Newton (a step from a state far
  // from equilibrium can overshoot even with a fresh tangent). The failed attempt's time
  // counts in the step's total.
  // So is one that had to be shortened at an obstacle, with the free configuration converged:
  // the barrier's stiffness grows without bound there, and from a state away from
  // equilibrium the shortened step's answers lay up to 2 mm from the equilibrium at their
  // pressure on the finger pressing a ball (docs/contact.md).
  if (one_step && (shortened_at_obstacle_ || !problem_.orientation_preserved(u))) {
    HS_PETSC(VecCopy(step_start_, u));
    constraints_.set_multipliers(step_start_pressures_);
    (fresh || shortened_at_obstacle_ ? retake_converged_ : force_refactor_) = true;
    return retake(
        u, targets, clock.start,
        shortened_at_obstacle_
            ? report.fallback + "; taken again with the free configuration converged by Newton"
            : "");
  }
  force_refactor_ = retake_converged_ = false;
  // Refined when every step factors (a kept factorization is for speed, and its chord step
  // from a stale tangent does not measure the distance to equilibrium: docs/control.md).
  if (config_.control->free_solve == FreeSolve::one_step && !config_.control->newton_finish &&
      config_.control->refactor_every == 1)
    refine(u, targets, report);
  finish_report(u, targets, clock, report);
  return report;
}

void InverseController::converge_free(Vec u, bool one_step, ControlStepReport& report,
                                      StepClock& clock) {
  const auto& timers = problem_.timers();
  clock.start = MPI_Wtime();
  problem_.begin_solve();  // friction lagged from the last answer (a one_step step has no Newton)
  clock.assembly0 = timers.residual_s + timers.jacobian_s;
  clock.fluid0 = constraints_.fluid_weight_seconds();
  for (const auto& a : actuators_) constraints_[a.constraint].hold_multiplier();
  if (contact_qp_) contact_qp_->begin_step(u);
  if (!one_step) {
    const NewtonResult free = solve_free(u, report);
    if (!free.converged)
      throw SolveError("control step: the free configuration did not converge (" + free.reason +
                       ", residual " + std::to_string(free.residual_norm) + ")");
  }
  clock.free = MPI_Wtime();
  clock.free_overhead = timers.residual_s + timers.jacobian_s - clock.assembly0 +
                        constraints_.fluid_weight_seconds() - clock.fluid0;
}

// The step taken again from u (the caller has set how); `why`, where not empty, leads the
// answer's fallback, and the failed attempt's time counts in its total.
ControlStepReport InverseController::retake(Vec u, const std::vector<ControlTarget>& targets,
                                            double started, const std::string& why) {
  ControlStepReport again = step(u, targets);
  if (!why.empty()) again.fallback = why + (again.fallback.empty() ? "" : "; " + again.fallback);
  again.total_ms += 1e3 * max_over_ranks(MPI_Wtime() - started, problem_.comm());
  return again;
}

// With control.refactor_every N > 1 (one_step only) the tangent, its factorization and the
// responses are kept for N steps: the free step is then a modified-Newton step on the fresh
// residual, and W is the compliance of up to N - 1 steps ago. After Newton the residual is the
// converged one (the free step is then round-off).
double InverseController::start_residual(Vec u, bool one_step, std::vector<double>& controls,
                                         bool& stale_failed) {
  problem_.apply_dirichlet(u, 1.0);
  bool ok = constraints_.residual(u, 1.0, R_, controls);
  PetscReal r_norm = 0;
  HS_PETSC(VecNorm(R_, NORM_2, &r_norm));
  ok &= std::isfinite(r_norm);
  // A correction made with a kept (stale) factorization can overshoot: then go back to the
  // start of the last step and take it again with a fresh one. Overshooting is an inverted
  // element, or a residual ten times the one at the last factorization: on the hydraulic
  // finger one stale step took it from 0.5 to ~140, and a fresh step taken from there
  // inverted an element. A residual that grew less also asks for a fresh factorization.
  const bool overshoot = !ok || r_norm > 10 * residual_at_factorization_;
  if (overshoot && one_step && steps_since_factorization_ > 0 && step_start_) {
    HS_PETSC(VecCopy(step_start_, u));
    constraints_.set_multipliers(step_start_pressures_);
    for (const auto& a : actuators_) constraints_[a.constraint].hold_multiplier();
    ok = constraints_.residual(u, 1.0, R_, controls);
    HS_PETSC(VecNorm(R_, NORM_2, &r_norm));
    stale_failed = true;
  }
  if (!ok) throw SolveError("control step: an element is inverted at the free configuration");
  if (!step_start_) HS_PETSC(VecDuplicate(u, step_start_.out()));
  HS_PETSC(VecCopy(u, step_start_));
  step_start_pressures_ = constraints_.multipliers();
  return r_norm;
}

bool InverseController::factor_if_due(Vec u, bool one_step, bool stale_failed, double r_norm,
                                      ControlStepReport& report, StepClock& clock) {
  // control.factor_threads > 0: every step linearises (the current tangent is the
  // correction's operator), and factors in line only without a usable preconditioner.
  const bool background = one_step && background_;
  ++step_count_;
  const bool refactor = !one_step || background || !factored_ || stale_failed || force_refactor_ ||
                        steps_since_factorization_ + 1 >= config_.control->refactor_every ||
                        r_norm > residual_at_factorization_ ||
                        problem_.pattern_version() != pattern_version_;
  bool fresh = refactor;  // factored at this step's state
  step_ksp_ = ksp_;
  clock.factor = clock.compliance = MPI_Wtime();
  if (!refactor) {
    ++steps_since_factorization_;
    system_.solve_residual(ksp_, R_);  // else solved with the responses
    return fresh;
  }
  if (keeps_factorization()) {
    if (!factored_at_) HS_PETSC(VecDuplicate(u, factored_at_.out()));
    HS_PETSC(VecCopy(u, factored_at_));
    factored_constraints_ = constraint_states(constraints_);
  }
  if (!constraints_.linearize(u, 1.0, J_, lin_))
    throw SolveError("control step: an element is inverted at the free configuration");
  clock.factor = MPI_Wtime();
  if (background) fresh = correct_in_background(stale_failed, report, clock);
  if (fresh) {
    clock.factor = MPI_Wtime();
    problem_.reset_if_pattern_grew(ksp_, pattern_version_);
    HS_PETSC(KSPSetOperators(ksp_, J_, J_));
    const OptionsScope scope(options_.database());  // its factor's options
    HS_PETSC(KSPSetUp(ksp_));
    report.negative_pivots = negative_pivots();
    clock.compliance = MPI_Wtime();
    if (!factor_responses(ksp_))
      throw SolveError("control step: the factorization of the tangent failed");
    report.staleness = 0;
    if (background) {
      background_->use_inline(step_count_);
      background_->submit_if_idle(J_, step_count_);
    }
  }
  factored_ = true;
  steps_since_factorization_ = 0;
  residual_at_factorization_ = r_norm;
  return fresh;
}

// The responses through a background factorization of an earlier state (GMRES preconditioned
// by it); true when the step must factor in line instead.
bool InverseController::correct_in_background(bool stale_failed, ControlStepReport& report,
                                              StepClock& clock) {
  const BackgroundFactorizations::Poll polled = background_->poll();
  report.background_failure = polled.error;
  bool fresh =
      polled.failed || !background_->has_preconditioner() || stale_failed || force_refactor_;
  if (!fresh) background_->submit_if_idle(J_, step_count_);
  clock.compliance = MPI_Wtime();
  if (!fresh) {
    report.staleness = step_count_ - background_->preconditioner_state();
    step_ksp_ = background_->correction(J_);
    fresh = !factor_responses(step_ksp_, &report.correction_iterations);
    if (fresh) report.background_failure = "the correction did not converge";
  }
  if (fresh) {
    HS_PETSC(KSPSetReusePreconditioner(ksp_, PETSC_FALSE));
    step_ksp_ = ksp_;
  }
  return fresh;
}

// The free step: the bordered elimination with the actuators' pressures held; u becomes
// x_free.
void InverseController::take_free_step(Vec u, const std::vector<double>& controls) {
  const Eigen::VectorXd zeta_free =
      system_.solve_dense(system_.residual_rhs(lin_, controls, actuated_));
  system_.step(zeta_free, free_step_);
  HS_PETSC(VecAXPY(u, 1.0, free_step_));  // x_free
  for (int c = 0; c < constraints_.size(); ++c)
    constraints_[c].set_multiplier(constraints_[c].multiplier() + zeta_free(c));
}

void InverseController::correct(Vec u, const Eigen::VectorXd& dl, ControlStepReport& report) {
  const int m = constraints_.size(), n = num_actuators();
  HS_PETSC(VecMAXPY(u, n, dl.data(), response_.data()));
  std::vector<double> lambda = constraints_.multipliers();
  Eigen::VectorXd dlambda = zeta_.topRows(m) * dl;
  if (contact_qp_) dlambda += contact_qp_->apply(u, contact_dforce_).topRows(m);
  for (int c = 0; c < m; ++c) lambda[c] += dlambda(c);
  constraints_.set_multipliers(lambda);
  for (const auto& a : actuators_) constraints_[a.constraint].hold_multiplier();
  keep_outside_obstacles(u, report);
  if (config_.control->newton_finish) {
    problem_.apply_dirichlet(u, 1.0);
    const NewtonResult r = newton_.solve(u, 1.0);
    report.newton_iterations += r.iterations;
    if (!r.converged)
      throw SolveError("control step: Newton at the new actuation did not converge (" + r.reason +
                       ")");
  } else {
    for (int c = 0; c < m; ++c) constraints_[c].update_measure(u);
  }
}

void InverseController::keep_outside_obstacles(Vec u, ControlStepReport& report) {
  shortened_at_obstacle_ = false;
  if (!problem_.has_contact()) return;
  if (!contact_move_) HS_PETSC(VecDuplicate(u, contact_move_.out()));
  HS_PETSC(VecWAXPY(contact_move_, -1.0, step_start_, u));
  const double alpha = problem_.contact_step_limit(step_start_, contact_move_, 1.0);
  if (!(alpha < 1)) return;
  HS_PETSC(VecWAXPY(u, alpha, contact_move_, step_start_));
  std::vector<double> lambda = constraints_.multipliers();
  for (size_t c = 0; c < lambda.size(); ++c)
    lambda[c] = step_start_pressures_[c] + alpha * (lambda[c] - step_start_pressures_[c]);
  constraints_.set_multipliers(lambda);
  for (const auto& a : actuators_) constraints_[a.constraint].hold_multiplier();
  shortened_at_obstacle_ = true;
  char note[160];
  std::snprintf(note, sizeof note,
                "the step was shortened to %.3g of its length: it carried a node into an obstacle "
                "or near a triangle of the contact surfaces",
                alpha);
  report.fallback += (report.fallback.empty() ? "" : "; ") + std::string(note);
}

void InverseController::finish_report(Vec u, const std::vector<ControlTarget>& targets,
                                      const StepClock& clock, ControlStepReport& report) {
  const MPI_Comm comm = problem_.comm();
  const double t_end = MPI_Wtime();
  report.reached = effectors_.positions(u);
  double error2 = 0;
  for (const auto& t : targets) {
    const int e = effectors_.index(t.effector);
    for (int d = 0; d < 3; ++d)
      if (effectors_.config(e).directions[d])
        error2 += std::pow(report.reached[3 * e + d] - t.position[d], 2);
  }
  report.error = std::sqrt(error2);
  for (const auto& a : actuators_)
    report.actuation.push_back(constraints_[a.constraint].multiplier());
  const auto& timers = problem_.timers();
  const double assembly = timers.residual_s + timers.jacobian_s - clock.assembly0;
  const double fluid = constraints_.fluid_weight_seconds() - clock.fluid0;
  report.assembly_ms = 1e3 * max_over_ranks(assembly, comm);
  report.fluid_weight_ms = 1e3 * max_over_ranks(fluid, comm);
  report.free_solve_ms = 1e3 * max_over_ranks(clock.free - clock.start - clock.free_overhead, comm);
  report.factorization_ms = 1e3 * max_over_ranks(clock.compliance - clock.factor, comm);
  report.compliance_ms = 1e3 * max_over_ranks(clock.qp - clock.compliance, comm);
  report.qp_ms = 1e3 * max_over_ranks(clock.correction - clock.qp, comm);
  report.correction_ms = 1e3 * max_over_ranks(t_end - clock.correction, comm);
  report.total_ms = 1e3 * max_over_ranks(t_end - clock.start, comm);
}

}  // namespace hs
