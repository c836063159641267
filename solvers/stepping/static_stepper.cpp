#include "solvers/stepping/static_stepper.hpp"

#include "common/deck_reader.hpp"
#include "solvers/petsc_check.hpp"
#include "solvers/petsc_handle.hpp"

namespace hs {
namespace {

// The fraction of the increment at which the tangent predictor takes its Newton step, whose
// result is scaled back by its inverse: the second-order part of that step grows with the bulk
// modulus (a fraction of 1e-3 left 40 % of it in a block at nu 0.4999, kappa = 5,000 mu), and
// the step starts from the run's first state, whose residual is zero, so the round-off of the
// difference alone bounds it from below.
constexpr double kPredictorFraction = 1e-6;

}  // namespace

bool predict_by_tangent(Problem& problem, NonlinearSolver& solver, Vec u, double s_from, double s) {
  VecHandle jump(problem.create_vector());
  HS_PETSC(VecCopy(u, jump));
  problem.apply_dirichlet(jump, s);
  HS_PETSC(VecAXPY(jump, -1.0, u));
  PetscReal size = 0;
  HS_PETSC(VecNorm(jump, NORM_INFINITY, &size));
  if (size == 0) return false;
  const double eps = kPredictorFraction;
  VecHandle u_eps(problem.create_vector()), du(problem.create_vector());
  HS_PETSC(VecWAXPY(u_eps, eps, jump, u));
  std::vector<double> no_multipliers;
  if (!solver.newton_step(u_eps, s_from + eps * (s - s_from), du, no_multipliers)) return false;
  problem.zero_constrained(du);  // the boundary's motion is the jump itself
  VecHandle predicted(problem.create_vector()), R(problem.create_vector());
  HS_PETSC(VecWAXPY(predicted, 1.0, jump, u));
  HS_PETSC(VecAXPY(predicted, 1.0 / eps, du));
  if (!problem.residual(predicted, s, R)) return false;  // it inverts an element
  HS_PETSC(VecCopy(predicted, u));
  return true;
}

StaticStepper::StaticStepper(const Config& config, Problem& problem, NonlinearSolver& solver,
                             SteppingStats& stats)
    : config_(config),
      problem_(problem),
      solver_(solver),
      stats_(stats),
      schedule_(load_schedule(config.time)),
      predictor_(problem) {
  stats.max_steps = max_substeps(static_cast<int64_t>(schedule_.size()));
}

std::optional<StepReport> StaticStepper::advance(Vec u) {
  const size_t k = next_;
  const double s_to = schedule_[k];
  std::vector<double> no_multipliers;
  VecHandle from(problem_.create_vector());
  auto attempt = [&](double s) {
    HS_PETSC(VecCopy(u, from));
    predictor_.predict(u, no_multipliers, s);
    if (!predictor_.has_previous())
      predict_by_tangent(problem_, solver_, u, predictor_.parameter(), s);
    problem_.apply_dirichlet(u, s);
    problem_.keep_outside_contact(from, u, s);
    const NewtonResult r = solver_.solve(u, s);
    if (r.converged)
      predictor_.accept(s);
    else
      predictor_.reject(u, no_multipliers);
    return r;
  };
  advance_with_cutback(
      predictor_.parameter(), s_to, config_.time.max_cutbacks, stats_, problem_.comm(), attempt,
      [&](double s, const NewtonResult&, const std::string& why) {
        fail_step(problem_, static_cast<int>(k + 1), "load factor " + std::to_string(s), why);
      });
  next_ = k + 1;
  StepReport step;
  step.index = static_cast<int>(next_);
  step.what = "load " + format_number(s_to);
  step.time = s_to;
  step.load_factor = s_to;
  step.output = done() || (static_cast<int>(next_) % config_.output.every) == 0;
  return step;
}

nlohmann::json StaticStepper::position() const {
  return {{"step", next_},
          {"load_factor", predictor_.parameter()},
          {"previous_load_factor", predictor_.previous_parameter()},
          {"has_previous", predictor_.has_previous()},
          {"last", done()}};
}

NamedVecs StaticStepper::checkpoint_fields(Vec u) const {
  return {{"displacement", u}, {"previous_displacement", predictor_.previous()}};
}

void StaticStepper::resume(const Restart& restart, Vec u) {
  const nlohmann::json& p = restart.position();
  next_ = p.at("step");
  restart.read("displacement", problem_, u);
  restart.read("previous_displacement", problem_, predictor_.previous());
  predictor_.resume(p.at("load_factor"), p.at("previous_load_factor"), p.at("has_previous"), {});
}

}  // namespace hs
