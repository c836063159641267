#include "solvers/bordered_newton.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "common/interrupt.hpp"
#include "solvers/incompressibility.hpp"
#include "solvers/residual_test.hpp"

namespace hs {

BorderedNewton::BorderedNewton(Problem& problem, ConstraintSet& constraints,
                               const SolverConfig& solver, TangentKind tangent)
    : problem_(problem),
      constraints_(constraints),
      tangent_(tangent),
      options_(kBorderedPrefix, solver, preset_options(solver.preset, tangent),
               SolverOptions::Reach::every_object),
      system_(problem, constraints, BorderedSystem::Order::per_constraint) {
  const OptionsScope scope(options_.database());  // the matrix's options too (-mat_view)
  J_ = MatHandle(problem.create_matrix(options_.factors_mixed()));
  R_ = VecHandle(problem.create_vector());
  HS_PETSC(VecDuplicate(R_, du_.out()));
  HS_PETSC(VecDuplicate(R_, u_trial_.out()));
  HS_PETSC(KSPCreate(problem.comm(), ksp_.out()));
  options_.attach(reinterpret_cast<PetscObject>(ksp_.get()));
  HS_PETSC(KSPSetOptionsPrefix(ksp_, kBorderedPrefix));
  HS_PETSC(KSPSetFromOptions(ksp_));
  // Its own Newton's: -hs_bordered_snes_max_it, reached by an unprefixed snes_max_it (deck or
  // command line) as every object's options are; -hs_bordered_monitor, or -hs_newton_monitor,
  // its name before each solver object had its own prefix.
  max_it_ = static_cast<int>(options_.get_int("snes_max_it", max_it_));
  // PETSc's names for the tolerances: snes_atol in N (else 1e-9 of the force scale),
  // snes_rtol relative to the first residual.
  atol_ = options_.get_real("snes_atol", -1);
  rtol_ = options_.get_real("snes_rtol", rtol_);
  monitor_ = options_.get_bool("monitor", options_.get_unprefixed_bool("hs_newton_monitor", false));
  volume_monitor_ = options_.get_unprefixed_bool("hs_volume_monitor", false);
}

NewtonResult BorderedNewton::solve(Vec u, double s) {
  const double t0 = MPI_Wtime();
  problem_.begin_solve();
  const auto& timers = problem_.timers();
  const double assembly_before = timers.residual_s + timers.jacobian_s;
  const NewtonResult result = solve_keeping_volumes(
      problem_, u, [&] { return solve_once(u, s); }, volume_monitor_);
  if (result.converged) problem_.accept_state(u, s);
  const double assembly = timers.residual_s + timers.jacobian_s - assembly_before;
  solve_s_ += MPI_Wtime() - t0 - assembly;
  return result;
}

NewtonResult BorderedNewton::solve_once(Vec u, double s) {
  const int m = constraints_.size();
  NewtonResult result;
  std::vector<double> c, g_norm(m, 0.0);
  std::vector<double> lambda = constraints_.multipliers();

  auto force_scale = [&]() {
    double F = load_norm_;
    for (int i = 0; i < m; ++i) F = std::max(F, std::abs(lambda[i]) * g_norm[i]);
    return std::max(F, 1e-300);
  };
  auto controls_met = [&](const std::vector<double>& cc) {
    for (int i = 0; i < m; ++i)
      if (std::abs(cc[i]) > 1e-10 * constraints_.control_scale(i)) return false;
    return true;
  };

  bool ok = constraints_.residual(u, s, R_, c);
  PetscReal r_norm = 0;
  HS_PETSC(VecNorm(R_, NORM_2, &r_norm));
  const double r0 = r_norm;
  double r_previous = r_norm, floor = 0;
  for (int it = 0;; ++it) {
    result.residual_norm = r_norm;
    if (!ok || !std::isfinite(r_norm)) {
      const std::string collapse = constraints_.collapse_reason();
      result.reason = ok ? "residual not finite" : collapse.empty() ? problem_.refusal() : collapse;
      break;
    }
    const double tolerance = atol_ >= 0 ? atol_ : 1e-9 * force_scale();
    if (monitor_) {
      HS_PETSC(PetscPrintf(problem_.comm(), "  %2d |R| %.3e (tol %.3e)", it, r_norm, tolerance));
      for (int i = 0; i < m; ++i)
        HS_PETSC(PetscPrintf(problem_.comm(), "  c%d/C %.3e p %.6g", i,
                             std::abs(c[i]) / constraints_.control_scale(i), lambda[i]));
      HS_PETSC(PetscPrintf(problem_.comm(), "\n"));
    }
    ResidualTest test{tolerance, rtol_, [&] { return problem_.residual_roundoff(u); },
                      constraints_.load_jump()};
    const std::string verdict =
        residual_verdict(test, it, r_norm, r0, r_previous, controls_met(c), floor);
    if (!verdict.empty()) {
      result.converged = true;
      result.reason = verdict;
      break;
    }
    r_previous = r_norm;
    if (it >= max_it_) {
      char why[160];
      std::snprintf(why, sizeof why, "maximum iterations, %d; tolerance %.3g N, floor %.3g N",
                    max_it_, tolerance, floor);
      result.reason = why;
      break;
    }
    // Between iterations: a Newton that cannot converge must not hold a signal back.
    stop_if_interrupted(problem_.comm());
    ++result.iterations;

    // Linearise, factor once, and solve for R, every g_c and every q_h.
    if (!constraints_.linearize(u, s, J_, lin_)) {
      result.reason = "inverted element";
      break;
    }
    const double tc = MPI_Wtime();
    reset_if_pattern_grew();
    HS_PETSC(KSPSetOperators(ksp_, J_, J_));
    for (int i = 0; i < m; ++i) HS_PETSC(VecNorm(lin_.g[i], NORM_2, &g_norm[i]));
    if (!system_.solve(ksp_, R_, lin_, &result.linear_iterations)) {
      result.reason = "linear solve failed";
      break;
    }
    system_.factor_dense(lin_);
    const Eigen::VectorXd zeta = system_.solve_dense(system_.residual_rhs(lin_, c));
    system_.step(zeta, du_);
    constraint_s_ += MPI_Wtime() - tc;

    if (!take_step(u, s, zeta, lambda, c, r_norm, result.reason)) break;
  }
  return result;
}

bool BorderedNewton::newton_step(Vec u, double s, Vec du, std::vector<double>& dmultipliers) {
  std::vector<double> c;
  if (!constraints_.residual(u, s, R_, c) || !constraints_.linearize(u, s, J_, lin_)) return false;
  reset_if_pattern_grew();
  HS_PETSC(KSPSetOperators(ksp_, J_, J_));
  if (!system_.solve(ksp_, R_, lin_)) return false;
  system_.factor_dense(lin_);
  const Eigen::VectorXd zeta = system_.solve_dense(system_.residual_rhs(lin_, c));
  system_.step(zeta, du);
  dmultipliers.assign(zeta.data(), zeta.data() + constraints_.size());
  return true;
}

void BorderedNewton::reset_if_pattern_grew() {
  problem_.reset_if_pattern_grew(ksp_, pattern_version_);
}

// Full Newton steps, halved only where the trial leaves the domain (an inverted element, a
// cavity volume <= 0, a value that is not finite). No descent test on |R|: a bending
// structure's first step from rest overshoots the residual by orders of magnitude (the spurious
// stretch of the linear rotation), and a merit test would crawl there; a diverging increment is
// caught by the iteration limit and cut back by the stepping. Self-contact is the exception.
bool BorderedNewton::take_step(Vec u, double s, const Eigen::VectorXd& zeta,
                               std::vector<double>& lambda, std::vector<double>& c, double& r_norm,
                               std::string& reason) {
  const int m = constraints_.size();
  std::vector<double> c_trial;
  // Self-contact's distances are unsigned: a step that carried a node through a triangle
  // would not be refused, so it is shortened first (SelfContact::step_limit).
  double t = problem_.self_contact_step_limit(u, du_);
  // Where self-contact's pairs act, at u or at the trial, full steps cycle on their stiff
  // barriers, whose Hessians jump between a triangle's regions (docs/contact.md,
  // "Self-contact"): a step is halved while it lowers neither |R| nor the energy, and the
  // trial of the smallest |R| is taken after four halvings.
  const SelfContact* self = problem_.self_contact();
  const bool pairs_at_u = self && self->last_pairs() > 0;
  std::string collapse;  // the last trial's collapsed cavity, if that was why it was refused
  // The point at u + t du, its multipliers and constraint values in `trial`, c_trial;
  // false where it leaves the domain.
  std::vector<double> trial;
  PetscReal norm = 0;
  auto evaluate = [&](double at) {
    HS_PETSC(VecWAXPY(u_trial_, at, du_, u));
    trial = lambda;
    for (int i = 0; i < m; ++i) trial[i] += at * zeta(i);
    constraints_.set_multipliers(trial);
    const bool ok = constraints_.residual(u_trial_, s, R_, c_trial);
    HS_PETSC(VecNorm(R_, NORM_2, &norm));
    bool finite = std::isfinite(norm);
    for (double x : c_trial) finite &= std::isfinite(x);
    collapse = constraints_.collapse_reason();
    return ok && finite;
  };
  auto accept = [&](double at) {
    if (monitor_) HS_PETSC(PetscPrintf(problem_.comm(), "      step %.3g of du\n", at));
    HS_PETSC(VecCopy(u_trial_, u));
    lambda = trial;
    c = c_trial;
    r_norm = norm;
    return true;
  };
  // With the cavities' pressures held, R is the gradient of an energy
  // (Problem::potential_energy): a step that lowers it by Armijo's rule is taken too, though
  // |R| rise, as incremental potential contact does. Where the exact tangent is indefinite
  // the step may climb the energy (R . du >= 0): then |R| alone decides.
  double energy_at_u = 0, slope = 0;
  bool energy_merit = self && problem_.has_potential_at_held_pressures() &&
                      constraints_.holds_pressures() && (zeta.array() == 0).all();
  if (energy_merit) {
    HS_PETSC(VecDot(R_, du_, &slope));
    energy_merit = slope < 0 && problem_.potential_energy(u, s, &energy_at_u);
  }
  auto lowers_energy = [&](double at) {
    double energy = 0;
    return energy_merit && problem_.potential_energy(u_trial_, s, &energy) &&
           energy <= energy_at_u + 1e-4 * at * slope;
  };
  double best_t = -1, best_norm = 0;
  for (int halving = 0; halving <= 8; ++halving, t /= 2) {
    if (!evaluate(t)) continue;
    const bool descend = pairs_at_u || (self && self->last_pairs() > 0);
    if (!descend || norm < r_norm || lowers_energy(t)) return accept(t);
    if (best_t < 0 || norm < best_norm) best_t = t, best_norm = norm;
    if (halving >= 4) break;
  }
  if (best_t > 0 && evaluate(best_t)) return accept(best_t);
  constraints_.set_multipliers(lambda);
  constraints_.residual(u, s, R_, c);  // leave the cavities at the last accepted point
  reason = !collapse.empty()            ? "every shortened step fails: " + collapse
           : problem_.contact_refused() ? "every shortened step fails: " + problem_.refusal()
                                        : "every shortened step inverts an element";
  return false;
}

}  // namespace hs
