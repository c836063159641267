#include "solvers/stepping.hpp"

#include <petscksp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

#include "common/error.hpp"
#include "common/interrupt.hpp"

namespace hs {

std::vector<double> load_schedule(const TimeConfig& time) {
  if (!time.schedule.empty()) return time.schedule;
  std::vector<double> s(time.steps);
  for (int k = 0; k < time.steps; ++k) s[k] = static_cast<double>(k + 1) / time.steps;
  return s;
}

namespace {

std::string newton_failure(const NewtonResult& r) {
  std::ostringstream msg;
  msg << "Newton did not converge (" << r.reason << ", residual " << r.residual_norm << " after "
      << r.iterations << " iterations)";
  return msg.str();
}

[[noreturn]] void fail(const Problem& problem, int step, const std::string& where,
                       const std::string& why) {
  std::string msg = "step " + std::to_string(step) + " (" + where + "): " + why;
  if (problem.inverted_element() >= 0)
    msg += "; element " + std::to_string(problem.inverted_element()) + " is inverted (det F <= 0)";
  throw SolveError(msg);
}

std::string g(double x) {
  std::ostringstream text;
  text << x;
  return text.str();
}

}  // namespace

static_assert(kMinIncrement == 0x1p-40, "the message names it");

int64_t max_substeps(int64_t planned) {
  return std::max(kMinSubstepsPerRun, kSubstepsPerPlannedStep * planned);
}

LoadStepper::LoadStepper(Problem& problem, NewtonSolver& newton, int max_cutbacks)
    : problem_(problem), newton_(newton), max_cutbacks_(max_cutbacks) {
  u_last_ = VecHandle(problem.create_vector());
  saved_ = VecHandle(problem.create_vector());
}

void LoadStepper::predict(Vec u, double s_next) {
  // u <- u + (s_next - s) / (s - s_last) (u - u_last): exact for a path linear in s.
  if (has_last_ && s_ != s_last_) {
    const double k = (s_next - s_) / (s_ - s_last_);
    HS_PETSC(VecAXPBY(u, -k, 1 + k, u_last_));  // u <- (1 + k) u - k u_last
  }
  problem_.apply_dirichlet(u, s_next);
}

void advance_with_cutback(
    double from, double to, int max_cutbacks, SteppingStats& stats, MPI_Comm comm,
    const std::function<NewtonResult(double)>& attempt,
    const std::function<void(double, const NewtonResult&, const std::string&)>& give_up) {
  double done = 0, increment = 1;      // fractions of the way from `from` to `to`
  double at = from;                    // the parameter of the last converged state
  int64_t halvings = 0, failures = 0;  // in a row; in this step
  const int64_t max_failures = int64_t{kCutbacksPerStepPerMaxCutbacks} * max_cutbacks;
  auto parameter = [&](double fraction) { return from + fraction * (to - from); };
  for (bool first = true; done < 1; first = false) {
    // A step that goes on past its first solve asks before each further one whether a
    // signal came (a step done in one solve is asked at its end, as every step).
    if (!first) stop_if_interrupted(comm);
    const double next = std::min(1.0, done + increment);
    const double t = parameter(next);
    const NewtonResult r = attempt(t);
    stats.newton_iterations += r.iterations;
    stats.linear_iterations += r.linear_iterations;
    if (r.converged) {
      done = next;
      at = t;
      ++stats.steps;
      halvings = 0;
      increment = std::min(1.0, 2 * increment);
      if (done < 1 && stats.max_steps > 0 && stats.steps >= stats.max_steps)
        give_up(t, r,
                "the run has taken " + std::to_string(stats.steps) +
                    " converged sub-steps, the most it may (" +
                    std::to_string(kSubstepsPerPlannedStep) + " per planned step, at least " +
                    std::to_string(kMinSubstepsPerRun) + "): give it more steps");
      continue;
    }
    ++stats.cutbacks;
    if (++halvings > max_cutbacks)
      give_up(t, r,
              newton_failure(r) + " after " + std::to_string(max_cutbacks) +
                  " halvings of the increment in a row (time.max_cutbacks)");
    if (++failures > max_failures)
      give_up(t, r,
              newton_failure(r) + "; the step was cut back " + std::to_string(max_failures) +
                  " times, the most a step may (" + std::to_string(kCutbacksPerStepPerMaxCutbacks) +
                  " x time.max_cutbacks)");
    increment /= 2;
    if (increment < kMinIncrement)
      give_up(t, r,
              newton_failure(r) + " with an increment of " + g(2 * increment) +
                  " of the step; a smaller one is below the least a step takes (2^-40 of it)");
    // An increment that no longer changes the parameter would solve the converged state
    // again, converge, and start over.
    if (parameter(std::min(1.0, done + increment)) == at)
      give_up(t, r,
              newton_failure(r) + "; halving the increment again would leave " + g(at) +
                  " unchanged in floating point");
  }
}

void LoadStepper::advance(Vec u, double s_to, int step, SteppingStats& stats) {
  auto attempt = [&](double s) {
    HS_PETSC(VecCopy(u, saved_));  // the converged state at s_
    predict(u, s);
    const NewtonResult r = newton_.solve(u, s);
    if (r.converged) {
      HS_PETSC(VecCopy(saved_, u_last_));
      s_last_ = s_;
      s_ = s;
      has_last_ = true;
    } else {
      HS_PETSC(VecCopy(saved_, u));  // back to the converged state; the history still holds
    }
    return r;
  };
  advance_with_cutback(s_, s_to, max_cutbacks_, stats, problem_.comm(), attempt,
                       [&](double s, const NewtonResult&, const std::string& why) {
                         fail(problem_, step, "load factor " + std::to_string(s), why);
                       });
}

void run_dynamic(Problem& problem, NewtonSolver& newton, const TimeConfig& time, Vec u,
                 SteppingStats& stats, const StepCallback& on_step, const DynamicResume* resume) {
  const bool newmark = time.integrator == Integrator::newmark;
  const double dt = time.dt, beta = time.newmark_beta, gamma = time.newmark_gamma;
  InertiaTerm inertia;
  VecHandle v, a, a_new, R, Mv, f_ext, scratch;
  // The problem lets go of the inertia before it is released, on every way out: a failed step
  // (SolveError) and a signal (Interrupted, from on_step) leave by an exception, which the
  // caller catches to keep the steps done.
  struct Unset {
    Problem& problem;
    ~Unset() { problem.set_inertia(nullptr); }
  } unset{problem};
  inertia.M = MatHandle(problem.create_mass_matrix());
  HS_PETSC(VecDuplicate(u, v.out()));
  HS_PETSC(VecDuplicate(u, a.out()));
  HS_PETSC(VecDuplicate(u, a_new.out()));
  HS_PETSC(VecDuplicate(u, R.out()));
  HS_PETSC(VecDuplicate(u, inertia.u_pred.out()));
  HS_PETSC(VecSet(v, 0.0));

  if (resume) {
    resume->fill(v, a);
  } else {
    // Initial acceleration from M a0 = -(f_int(u0) - f_ext): CG on the mass matrix.
    problem.apply_dirichlet(u, 1.0);
    problem.residual(u, 1.0, R);
    KspHandle mass_solver;
    HS_PETSC(KSPCreate(problem.comm(), mass_solver.out()));
    HS_PETSC(KSPSetOperators(mass_solver, inertia.M, inertia.M));
    HS_PETSC(KSPSetType(mass_solver, KSPCG));
    PC pc;
    HS_PETSC(KSPGetPC(mass_solver, &pc));
    HS_PETSC(PCSetType(pc, PCJACOBI));
    HS_PETSC(KSPSetTolerances(mass_solver, 1e-12, 1e-30, PETSC_DEFAULT, 1000));
    HS_PETSC(KSPSolve(mass_solver, R, a));
    HS_PETSC(VecScale(a, -1.0));
  }

  // E = 1/2 v.M v + int psi - f_ext.u (f_ext at full load on the current configuration).
  HS_PETSC(VecDuplicate(u, Mv.out()));
  HS_PETSC(VecDuplicate(u, f_ext.out()));
  HS_PETSC(VecDuplicate(u, scratch.out()));
  auto total_energy = [&]() {
    double stored = 0, kinetic = 0, work = 0;
    problem.internal_force(u, scratch, &stored);
    HS_PETSC(MatMult(inertia.M, v, Mv));
    HS_PETSC(VecDot(v, Mv, &kinetic));
    problem.external_load(u, 1.0, f_ext);
    HS_PETSC(VecDot(f_ext, u, &work));
    stats.max_stored_energy = std::max(stats.max_stored_energy, stored);
    return 0.5 * kinetic + stored - work;
  };
  if (!resume) stats.energy.push_back(total_energy());

  problem.set_inertia(&inertia);
  const int nsteps = static_cast<int>(std::ceil(time.end_time / dt - 1e-9));
  for (int n = resume ? resume->step + 1 : 1; n <= nsteps; ++n) {
    // u_pred = u + dt v + dt^2 (1/2 - beta) a  (Newmark), u + dt v (backward Euler);
    // the step solves c M (u - u_pred) + f_int(u) - f_ext = 0, c = 1/(beta dt^2) or 1/dt^2.
    HS_PETSC(VecWAXPY(inertia.u_pred, dt, v, u));
    if (newmark) HS_PETSC(VecAXPY(inertia.u_pred, dt * dt * (0.5 - beta), a));
    inertia.c = newmark ? 1 / (beta * dt * dt) : 1 / (dt * dt);
    const NewtonResult r = newton.solve(u, 1.0);
    stats.newton_iterations += r.iterations;
    stats.linear_iterations += r.linear_iterations;
    if (!r.converged) fail(problem, n, "time " + std::to_string(n * dt), newton_failure(r));
    ++stats.steps;
    // a_new = c (u - u_pred); v += dt ((1 - gamma) a + gamma a_new) or dt a_new.
    HS_PETSC(VecWAXPY(a_new, -1.0, inertia.u_pred, u));
    HS_PETSC(VecScale(a_new, inertia.c));
    if (newmark) {
      HS_PETSC(VecAXPY(v, dt * (1 - gamma), a));
      HS_PETSC(VecAXPY(v, dt * gamma, a_new));
    } else {
      HS_PETSC(VecAXPY(v, dt, a_new));
    }
    HS_PETSC(VecCopy(a_new, a));
    stats.energy.push_back(total_energy());
    on_step(n, n * dt, u, v, a);
  }
}

}  // namespace hs
