#include "solvers/inverse_controller.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "common/error.hpp"
#include "control/qp.hpp"
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
      effectors_(effectors) {
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
  J_ = MatHandle(problem.create_matrix());
  HS_PETSC(KSPCreate(problem.comm(), ksp_.out()));
  HS_PETSC(KSPSetFromOptions(ksp_));
  if (config.control->factor_threads > 0 && config.control->free_solve == FreeSolve::one_step)
    background_ = std::make_unique<BackgroundFactorizations>(
        problem.comm(), config.control->factor_threads, ksp_, kCorrectionRtol);
  for (int c = 0; c < constraints.size(); ++c) {
    Y_.push_back(problem.create_vector());
    if (constraints[c].measure_load()) Z_.push_back(problem.create_vector());
  }
  for (size_t a = 0; a < actuators_.size(); ++a) response_.push_back(problem.create_vector());
  R_ = VecHandle(problem.create_vector());
  a_ = VecHandle(problem.create_vector());
  free_step_ = VecHandle(problem.create_vector());
}

InverseController::~InverseController() {
  background_.reset();  // it holds ksp_ (not owning it): it goes first
}

// Y_c = K^-1 g_c, Z_h = K^-1 q_h with the current factorization; the dense system S of the
// bordered elimination for zeta = [dlambda (m); eta]: du = -a + [Y Z] zeta, actuators' rows
// take their input, the other cavities keep their control (alpha g^T du + b dlambda = -c),
// eta_h = g_h^T du; and the response of the whole system to each actuator.
// a_ = K^-1 R_ is solved with them, all through the factors at once.
bool InverseController::factor_responses(KSP ksp, int* iterations) {
  const int m = constraints_.size(), n = num_actuators();
  columns_.clear();
  weighted_.clear();
  std::vector<Vec> rhs{R_};
  for (int c = 0; c < m; ++c) {
    rhs.push_back(lin_.g[c]);
    columns_.push_back(Y_[c]);
  }
  for (int c = 0, h = 0; c < m; ++c)
    if (lin_.q[c]) {
      rhs.push_back(lin_.q[c]);
      columns_.push_back(Z_[h++]);
      weighted_.push_back(c);
    }
  std::vector<Vec> solutions{a_};
  solutions.insert(solutions.end(), columns_.begin(), columns_.end());
  if (!solve_columns(ksp, rhs, solutions, iterations)) return false;
  const int k = static_cast<int>(columns_.size());
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(k, k), inputs = Eigen::MatrixXd::Zero(k, n);
  std::vector<PetscScalar> dots(k);
  actuated_.assign(m, false);
  for (int a = 0; a < n; ++a) {
    actuated_[actuators_[a].constraint] = true;
    inputs(actuators_[a].constraint, a) = 1;
  }
  for (int c = 0; c < m; ++c) {
    if (actuated_[c]) {
      S(c, c) = 1;
      continue;
    }
    HS_PETSC(VecMDot(lin_.g[c], k, columns_.data(), dots.data()));
    for (int j = 0; j < k; ++j) S(c, j) = lin_.alpha[c] * dots[j];
    S(c, c) += lin_.b[c];
  }
  for (size_t w = 0; w < weighted_.size(); ++w) {
    const int row = m + static_cast<int>(w);
    HS_PETSC(VecMDot(lin_.g[weighted_[w]], k, columns_.data(), dots.data()));
    for (int j = 0; j < k; ++j) S(row, j) = dots[j];
    S(row, row) -= 1;
  }
  S_lu_.compute(S);
  zeta_ = S_lu_.solve(inputs);  // k x n
  for (int a = 0; a < n; ++a) {
    HS_PETSC(VecSet(response_[a], 0.0));
    const Eigen::VectorXd z = zeta_.col(a);
    HS_PETSC(VecMAXPY(response_[a], k, z.data(), columns_.data()));
  }
  return true;
}

ControlStepReport InverseController::step(Vec u, const std::vector<ControlTarget>& targets) {
  ControlStepReport report;
  const MPI_Comm comm = problem_.comm();
  const double t_start = MPI_Wtime();
  const auto& timers = problem_.timers();
  const double assembly0 = timers.residual_s + timers.jacobian_s;
  const double fluid0 = constraints_.fluid_weight_seconds();
  const int m = constraints_.size(), n = num_actuators();

  // Step 1: the free configuration at the current actuation, converged by Newton; in the
  // one_step mode it is the first Newton step of step 2's linearisation instead.
  const bool one_step = config_.control->free_solve == FreeSolve::one_step && !retake_converged_;
  for (const auto& a : actuators_) {
    Constraint& c = constraints_[a.constraint];
    c.control = Constraint::Control::multiplier;
    c.target = c.lambda;
  }
  if (!one_step) {
    const NewtonResult free = solve_free(u, report);
    if (!free.converged)
      throw SolveError("control step: the free configuration did not converge (" + free.reason +
                       ", residual " + std::to_string(free.residual_norm) + ")");
  }
  const double t_free = MPI_Wtime();
  const double free_overhead = timers.residual_s + timers.jacobian_s - assembly0 +
                               constraints_.fluid_weight_seconds() - fluid0;

  // Step 2: one linearisation, one factorization, and the response to each actuator. After
  // Newton the residual is the converged one (the free step below is then round-off). With
  // control.refactor_every N > 1 (one_step only) the tangent, its factorization and the
  // responses are kept for N steps: the free step is then a modified-Newton step on the
  // fresh residual, and W is the compliance of up to N - 1 steps ago.
  std::vector<double> controls;
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
  bool stale_failed = false;
  if (overshoot && one_step && steps_since_factorization_ > 0 && step_start_) {
    HS_PETSC(VecCopy(step_start_, u));
    constraints_.set_multipliers(step_start_pressures_);
    for (const auto& a : actuators_)
      constraints_[a.constraint].target = constraints_[a.constraint].lambda;
    ok = constraints_.residual(u, 1.0, R_, controls);
    HS_PETSC(VecNorm(R_, NORM_2, &r_norm));
    stale_failed = true;
  }
  if (!ok) throw SolveError("control step: an element is inverted at the free configuration");
  if (one_step) {
    if (!step_start_) HS_PETSC(VecDuplicate(u, step_start_.out()));
    HS_PETSC(VecCopy(u, step_start_));
    step_start_pressures_ = constraints_.multipliers();
  }
  // control.factor_threads > 0: every step linearises (the current tangent is the
  // correction's operator), and factors in line only without a usable preconditioner.
  const bool background = one_step && background_;
  ++step_count_;
  const bool refactor = !one_step || background || !factored_ || stale_failed || force_refactor_ ||
                        steps_since_factorization_ + 1 >= config_.control->refactor_every ||
                        r_norm > residual_at_factorization_;
  bool fresh = refactor;  // factored at this step's state
  const double t_factor0 = MPI_Wtime();
  double t_factor = t_factor0, t_compliance = t_factor0;
  if (refactor) {
    if (keeps_factorization()) {
      if (!factored_at_) HS_PETSC(VecDuplicate(u, factored_at_.out()));
      HS_PETSC(VecCopy(u, factored_at_));
      factored_constraints_ = constraint_states(constraints_);
    }
    if (!constraints_.linearize(u, 1.0, J_, lin_))
      throw SolveError("control step: an element is inverted at the free configuration");
    t_factor = MPI_Wtime();
    if (background) {
      const BackgroundFactorizations::Poll polled = background_->poll();
      report.background_failure = polled.error;
      fresh =
          polled.failed || !background_->has_preconditioner() || stale_failed || force_refactor_;
      if (!fresh) background_->submit_if_idle(J_, step_count_);
      t_compliance = MPI_Wtime();
      if (!fresh) {
        report.staleness = step_count_ - background_->preconditioner_state();
        fresh = !factor_responses(background_->correction(J_), &report.correction_iterations);
        if (fresh) report.background_failure = "the correction did not converge";
      }
      if (fresh) HS_PETSC(KSPSetReusePreconditioner(ksp_, PETSC_FALSE));
    }
    if (fresh) {
      t_factor = MPI_Wtime();
      HS_PETSC(KSPSetOperators(ksp_, J_, J_));
      HS_PETSC(KSPSetUp(ksp_));
      t_compliance = MPI_Wtime();
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
  } else {
    ++steps_since_factorization_;
  }
  const int k = static_cast<int>(columns_.size());
  if (!refactor) HS_PETSC(KSPSolve(ksp_, R_, a_));  // else solved with the responses
  // The free step: the bordered elimination with the actuators' pressures held.
  Eigen::VectorXd free_rhs = Eigen::VectorXd::Zero(k);
  PetscScalar ga = 0;
  for (int c = 0; c < m; ++c) {
    if (actuated_[c]) continue;
    HS_PETSC(VecDot(lin_.g[c], a_, &ga));
    free_rhs(c) = -controls[c] + lin_.alpha[c] * ga;
  }
  for (size_t w = 0; w < weighted_.size(); ++w) {
    HS_PETSC(VecDot(lin_.g[weighted_[w]], a_, &ga));
    free_rhs(m + static_cast<int>(w)) = ga;
  }
  const Eigen::VectorXd zeta_free = S_lu_.solve(free_rhs);
  HS_PETSC(VecCopy(a_, free_step_));
  HS_PETSC(VecScale(free_step_, -1.0));
  HS_PETSC(VecMAXPY(free_step_, k, zeta_free.data(), columns_.data()));
  HS_PETSC(VecAXPY(u, 1.0, free_step_));  // x_free
  for (int c = 0; c < m; ++c) constraints_[c].lambda += zeta_free(c);
  // Effector rows (weighted, controlled directions of the targeted effectors) and volumes.
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
  Eigen::MatrixXd W(rows_W.size(), n), growth(n, n);
  Eigen::VectorXd delta(rows_W.size());
  for (size_t r = 0; r < rows_W.size(); ++r) {
    for (int a = 0; a < n; ++a) W(r, a) = rows_W[r][a];
    delta(r) = rows_delta[r];
  }
  for (int a = 0; a < n; ++a) {
    HS_PETSC(VecMDot(lin_.g[actuators_[a].constraint], n, response_.data(), wdots.data()));
    for (int b = 0; b < n; ++b) growth(a, b) = wdots[b];
  }
  const double t_qp = MPI_Wtime();

  // Step 3: the QP for the pressure changes.
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
  for (int a = 0; a < n; ++a) {
    const auto& b = actuators_[a].config;
    const double lambda = constraints_[actuators_[a].constraint].lambda;
    PetscScalar free_growth = 0;  // the free step's volume change (linear)
    HS_PETSC(VecDot(lin_.g[actuators_[a].constraint], free_step_, &free_growth));
    const double grown =
        constraints_[actuators_[a].constraint].measure + free_growth - actuators_[a].rest_measure;
    Eigen::RowVectorXd unit = Eigen::RowVectorXd::Zero(n);
    unit(a) = 1;
    bound(unit, b.min_multiplier - lambda, a);
    bound(-unit, lambda - b.max_multiplier, a);
    bound(unit, -b.max_multiplier_step, a);
    bound(-unit, -b.max_multiplier_step, a);
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
  const double t_correction = MPI_Wtime();

  // Step 4: correction x = x_free + sum_a du_a dl_a, and the pressures of every cavity.
  HS_PETSC(VecMAXPY(u, n, dl.data(), response_.data()));
  std::vector<double> lambda = constraints_.multipliers();
  const Eigen::VectorXd dlambda = zeta_.topRows(m) * dl;
  for (int c = 0; c < m; ++c) lambda[c] += dlambda(c);
  constraints_.set_multipliers(lambda);
  for (const auto& a : actuators_)
    constraints_[a.constraint].target = constraints_[a.constraint].lambda;
  if (config_.control->newton_finish) {
    problem_.apply_dirichlet(u, 1.0);
    const NewtonResult r = newton_.solve(u, 1.0);
    report.newton_iterations += r.iterations;
    if (!r.converged)
      throw SolveError("control step: Newton at the new actuation did not converge (" + r.reason +
                       ")");
  } else {
    for (int c = 0; c < m; ++c) constraints_[c].measure = constraints_.measure(c, u);
  }
  // A one-linearisation correction that inverts an element is taken again at once, so that
  // no step hands out (or writes) an inverted body: with a fresh factorization if it used a
  // kept one, else with the free configuration converged by Newton (a step from a state far
  // from equilibrium can overshoot even with a fresh tangent). The failed attempt's time
  // counts in the step's total.
  if (one_step && !problem_.orientation_preserved(u)) {
    HS_PETSC(VecCopy(step_start_, u));
    constraints_.set_multipliers(step_start_pressures_);
    (fresh ? retake_converged_ : force_refactor_) = true;
    ControlStepReport again = step(u, targets);
    again.total_ms += 1e3 * max_over_ranks(MPI_Wtime() - t_start, comm);
    return again;
  }
  force_refactor_ = retake_converged_ = false;
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
  for (const auto& a : actuators_) report.actuation.push_back(constraints_[a.constraint].lambda);
  const double assembly = timers.residual_s + timers.jacobian_s - assembly0;
  const double fluid = constraints_.fluid_weight_seconds() - fluid0;
  report.assembly_ms = 1e3 * max_over_ranks(assembly, comm);
  report.fluid_weight_ms = 1e3 * max_over_ranks(fluid, comm);
  report.free_solve_ms = 1e3 * max_over_ranks(t_free - t_start - free_overhead, comm);
  report.factorization_ms = 1e3 * max_over_ranks(t_compliance - t_factor, comm);
  report.compliance_ms = 1e3 * max_over_ranks(t_qp - t_compliance, comm);
  report.qp_ms = 1e3 * max_over_ranks(t_correction - t_qp, comm);
  report.correction_ms = 1e3 * max_over_ranks(t_end - t_correction, comm);
  report.total_ms = 1e3 * max_over_ranks(t_end - t_start, comm);
  return report;
}

}  // namespace hs
