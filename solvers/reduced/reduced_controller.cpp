#include "solvers/reduced/reduced_controller.hpp"

#include <algorithm>
#include <cmath>

#include "common/error.hpp"
#include "control/actuation_qp.hpp"

namespace hs {
namespace {

constexpr int kMaxStepIterations = 30;  // of one step
// An iteration at equilibrium whose actuation change moves no targeted effector by more than
// this (m, weighted as in the QP) ends the step: 50 times below the accuracy asked of a
// reduced model (0.5 mm).
constexpr double kEffectorStop = 1e-5;
// A step that leaves a residual above this fraction of the forces is solved to equilibrium
// before the next iteration.
constexpr double kFarResidual = 0.5;
// After this many iterations of one step every move is solved to equilibrium (QP, then
// Newton: slower, but the iterations can no longer cycle through loose linearizations, as
// they did near a soft finger's limit point, 1-2 mm short of reachable targets).
constexpr int kLooseIterations = 10;

}  // namespace

ReducedController::ReducedController(const Config& config, Problem& problem,
                                     ConstraintSet& constraints, Effectors& effectors)
    : config_(config),
      constraints_(constraints),
      effectors_(effectors),
      path_(config.control->reduced_model) {
  model_ = read_reduced_model(path_);
  std::vector<Vec> rows;
  for (int e = 0; e < effectors.size(); ++e)
    for (int d = 0; d < 3; ++d) rows.push_back(effectors.row(e, d));
  system_ = std::make_unique<ReducedSystem>(config, problem, constraints, model_, path_, rows);
  for (const auto& a : config.control->actuators)
    actuators_.push_back(constraints.find(a.constraint));
  effector_rows_.resize(rows.size(), system_->size());
  for (size_t r = 0; r < rows.size(); ++r) effector_rows_.row(r) = system_->project_row(rows[r]);
  VecHandle zero(problem.create_vector());
  reference_ = effectors.positions(zero);
  const Eigen::VectorXd reference =
      Eigen::Map<const Eigen::VectorXd>(reference_.data(), reference_.size());
  training_positions_ =
      (effector_rows_ * system_->training_states().transpose()).colwise() + reference;
  if (config.control->error_indicator)
    indicator_ =
        std::make_unique<ResidualErrorIndicator>(problem, constraints, *system_, actuators_, rows);
}

void ReducedController::set_rest(Vec u) {
  kept_.reset();
  q_ = system_->project(u);
  for (int c : actuators_) constraints_[c].hold_multiplier();
  const ReducedSolve r = system_->solve(q_, u);
  if (!r.converged)
    throw SolveError("reduced model: no reduced equilibrium at the rest state (" + r.reason + ")");
  rest_measure_.clear();
  for (int c : actuators_) rest_measure_.push_back(constraints_[c].measure());
  system_->place(q_, u, true);
}

double ReducedController::target_distance(const Eigen::VectorXd& x,
                                          const std::vector<ControlTarget>& targets) const {
  double d2 = 0;
  for (const auto& t : targets) {
    const int e = effectors_.index(t.effector);
    const auto& ec = effectors_.config(e);
    for (int d = 0; d < 3; ++d)
      if (ec.directions[d]) d2 += std::pow(ec.weight * (x(3 * e + d) - t.position[d]), 2);
  }
  return std::sqrt(d2);
}

Eigen::Index ReducedController::training_start(const std::vector<ControlTarget>& targets,
                                               const std::vector<ActuatorPosition>& at) const {
  const int n = static_cast<int>(actuators_.size());
  int directions = 0;  // with fewer than n, the answer depends on the start: none is chosen
  for (const auto& t : targets)
    for (int d = 0; d < 3; ++d)
      directions += effectors_.config(effectors_.index(t.effector)).directions[d];
  if (directions < n) return -1;
  double best = target_distance(effector_positions(q_), targets);
  Eigen::Index chosen = -1;
  for (Eigen::Index s = 0; s < training_positions_.cols(); ++s) {
    bool inside = true;  // within the step's change of the actuation
    for (int a = 0; a < n; ++a)
      inside &= std::abs(system_->training_actuations()(s, a) - at[a].origin) <=
                config_.control->actuators[a].max_multiplier_step;
    const double d = target_distance(training_positions_.col(s), targets);
    if (inside && d < 0.5 * best) {
      best = d;
      chosen = s;
    }
  }
  return chosen;
}

ReducedLinearization ReducedController::start(Vec u, const std::vector<ControlTarget>& targets,
                                              const std::vector<ActuatorPosition>& at) {
  const int n = static_cast<int>(actuators_.size());
  const Eigen::Index chosen = training_start(targets, at);
  ReducedLinearization L;
  if (chosen >= 0) {
    const Eigen::VectorXd q_start = q_;
    for (int a = 0; a < n; ++a)
      constraints_[actuators_[a]].prescribe(Constraint::Control::multiplier,
                                            system_->training_actuations()(chosen, a));
    q_ = system_->training_states().row(chosen).transpose();
    if (system_->linearize(q_, u, L, steps_ == 0)) return L;
    for (int a = 0; a < n; ++a)  // outside the model's domain: the step starts where it was
      constraints_[actuators_[a]].prescribe(Constraint::Control::multiplier, at[a].origin);
    q_ = q_start;
  } else if (kept_) {
    return *kept_;
  }
  if (!system_->linearize(q_, u, L, steps_ == 0))
    throw SolveError("reduced model: the step's start is outside the model's domain");
  return L;
}

void ReducedController::recover(Vec u) {
  kept_.reset();
  q_ = system_->project(u);
  system_->solve(q_, u);
  system_->place(q_, u, true);
}

Eigen::VectorXd ReducedController::effector_positions(const Eigen::VectorXd& q) const {
  return Eigen::Map<const Eigen::VectorXd>(reference_.data(), reference_.size()) +
         effector_rows_ * q;
}

void ReducedController::target_rows(const std::vector<ControlTarget>& targets,
                                    const Eigen::VectorXd& q, const Eigen::MatrixXd& dq,
                                    Eigen::MatrixXd& W, Eigen::VectorXd& delta) const {
  const Eigen::VectorXd x = effector_positions(q);
  std::vector<Eigen::RowVectorXd> rows;
  std::vector<double> distances;
  for (const auto& t : targets) {
    const int e = effectors_.index(t.effector);
    const auto& ec = effectors_.config(e);
    for (int d = 0; d < 3; ++d) {
      if (!ec.directions[d]) continue;
      rows.push_back(ec.weight * effector_rows_.row(3 * e + d) * dq);
      distances.push_back(ec.weight * (x(3 * e + d) - t.position[d]));
    }
  }
  W.resize(rows.size(), dq.cols());
  delta.resize(rows.size());
  for (size_t r = 0; r < rows.size(); ++r) {
    W.row(r) = rows[r];
    delta(r) = distances[r];
  }
}

bool ReducedController::move(Vec u, const Eigen::VectorXd& dq, const Eigen::VectorXd& dl,
                             ReducedLinearization& L, ControlStepReport& report, double far) {
  const int n = static_cast<int>(actuators_.size());
  const Eigen::VectorXd q_start = q_;
  Eigen::VectorXd lambda_start(n);
  for (int a = 0; a < n; ++a) lambda_start(a) = constraints_[actuators_[a]].multiplier();
  ReducedLinearization next;
  auto actuate = [&](double t) {
    const Eigen::VectorXd lambda = lambda_start + t * dl;
    for (int a = 0; a < n; ++a)
      constraints_[actuators_[a]].prescribe(Constraint::Control::multiplier, lambda(a));
    return lambda;
  };
  auto lands_near = [&](bool valid) {
    return valid && next.r.norm() <= std::max(L.r.norm(), far * std::max(L.scale, next.scale));
  };
  auto accept = [&](const Eigen::VectorXd& q) {
    q_ = q;
    L = next;
    return true;
  };
  // A step that lands near equilibrium goes on as one Newton iteration. While the iterations
  // may stay loose (far > 0), so does a fraction of it, or the nearest training sample where
  // it is the equilibrium at the fraction's actuation (a step to a bound): one linearization
  // each, before any step is solved to equilibrium. Near the top of a nearly incompressible
  // finger's range the equilibrium at a fixed pressure is nearly singular, and that solve took
  // steps of 1/32 for 25 iterations at each halving (docs/reduced_models.md, "Silicone").
  for (int halving = 0; far > 0 && halving < 6; ++halving) {
    const double t = std::ldexp(1.0, -halving);
    const Eigen::VectorXd lambda = actuate(t);
    const Eigen::VectorXd q = q_start + t * dq;
    if (lands_near(system_->linearize(q, u, next, false))) return accept(q);
    const Eigen::VectorXd sampled = system_->nearest_training_state(lambda);
    if (system_->linearize(sampled, u, next, false) && system_->balanced(next))
      return accept(sampled);
  }
  // One that lands far off (a large change of the actuation: the finger stiffens as it
  // inflates) is solved to equilibrium at its actuation, from there or from the nearest
  // training sample.
  for (int halving = 0; halving < 6; ++halving) {
    const double t = std::ldexp(1.0, -halving);
    const Eigen::VectorXd lambda = actuate(t);
    Eigen::VectorXd q = q_start + t * dq;
    const bool valid = system_->linearize(q, u, next, false);
    if (lands_near(valid)) return accept(q);
    const Eigen::VectorXd sampled = system_->nearest_training_state(lambda);
    if (!valid || system_->residual_norm(sampled, u) < next.r.norm()) q = sampled;
    const ReducedSolve solved = system_->solve(q, u);
    report.newton_iterations += solved.iterations;
    if (solved.converged && system_->linearize(q, u, next, false)) return accept(q);
  }
  for (int a = 0; a < n; ++a)
    constraints_[actuators_[a]].prescribe(Constraint::Control::multiplier, lambda_start(a));
  q_ = q_start;
  system_->linearize(q_, u, L, false);
  return false;
}

ControlStepReport ReducedController::step(Vec u, const std::vector<ControlTarget>& targets) {
  ControlStepReport report;
  const double t0 = MPI_Wtime();
  const double elements0 = system_->element_seconds(), forces0 = system_->constraint_seconds();
  const double fluid0 = constraints_.fluid_weight_seconds();
  double qp_s = 0;
  const int n = static_cast<int>(actuators_.size());
  std::vector<ActuatorPosition> at(n);
  for (int a = 0; a < n; ++a) {
    constraints_[actuators_[a]].hold_multiplier();
    at[a].origin = constraints_[actuators_[a]].multiplier();
  }
  // Newton on the equilibrium and the QP's optimality together: each iteration solves the QP
  // on the equations linearized at (q, lambda), r + K dq - G dl = 0, and steps both.
  ReducedLinearization L = start(u, targets, at);
  kept_.reset();
  Eigen::MatrixXd W;
  Eigen::VectorXd delta;
  bool done = false;
  for (int iteration = 0; iteration < kMaxStepIterations && !done; ++iteration) {
    Eigen::MatrixXd Ga(L.K.rows(), n);
    for (int a = 0; a < n; ++a) Ga.col(a) = L.G.col(actuators_[a]);
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu = L.K.partialPivLu();
    const Eigen::VectorXd free = lu.solve(-L.r);  // Newton's step at a fixed actuation
    const Eigen::MatrixXd dq = lu.solve(Ga);      // the compliance dq/dlambda
    target_rows(targets, q_ + free, dq, W, delta);
    for (int a = 0; a < n; ++a) {
      const Constraint& c = constraints_[actuators_[a]];
      at[a].multiplier = c.multiplier();
      at[a].grown = c.measure() - rest_measure_[a];
    }
    const double q0 = MPI_Wtime();
    const ActuationChange change =
        solve_actuation_qp(W, delta, Ga.transpose() * dq, config_.control->actuators, at,
                           config_.control->regularization);
    qp_s += MPI_Wtime() - q0;
    report.qp_solved = change.solved;
    report.qp_status = change.status;
    report.kkt_residual = change.kkt_residual;
    report.saturated = change.saturated;
    if (!change.solved) break;
    // Done at an equilibrium where the change would move no targeted effector by more than
    // kEffectorStop.
    done = system_->balanced(L) && (W * change.dl).lpNorm<Eigen::Infinity>() <= kEffectorStop;
    if (done) break;
    if (!move(u, free + dq * change.dl, change.dl, L, report,
              iteration < kLooseIterations ? kFarResidual : 0.0)) {
      report.limit_point = true;
      break;
    }
    ++report.newton_iterations;
  }
  if (system_->balanced(L)) {
    kept_ = L;
  } else {  // the answer is an equilibrium at its actuation, always
    const ReducedSolve solved = system_->solve(q_, u);
    report.newton_iterations += solved.iterations;
    if (!solved.converged)
      throw SolveError("reduced model: no equilibrium at the step's actuation (" + solved.reason +
                       ")");
  }
  ++steps_;
  const Eigen::VectorXd x = effector_positions(q_);
  report.reached.assign(x.data(), x.data() + x.size());
  double error2 = 0;
  for (const auto& t : targets) {
    const int e = effectors_.index(t.effector);
    for (int d = 0; d < 3; ++d)
      if (effectors_.config(e).directions[d]) error2 += std::pow(x(3 * e + d) - t.position[d], 2);
  }
  report.error = std::sqrt(error2);
  bool inside = true;
  for (int a = 0; a < n; ++a) {
    const double lambda = constraints_[actuators_[a]].multiplier();
    report.actuation.push_back(lambda);
    const double slack = 1e-9 * std::max(1.0, model_.upper[a] - model_.lower[a]);
    inside &= lambda >= model_.lower[a] - slack && lambda <= model_.upper[a] + slack;
  }
  // The parts: the elements and the constraints' forces (assembly), the liquid's weight, the
  // QP, and the rest (the reduced linear algebra) as the free solve.
  const double fluid = constraints_.fluid_weight_seconds() - fluid0;
  const double evaluations =
      system_->element_seconds() - elements0 + system_->constraint_seconds() - forces0;
  report.fluid_weight_ms = 1e3 * fluid;
  report.assembly_ms = 1e3 * (evaluations - fluid);
  report.qp_ms = 1e3 * qp_s;
  report.total_ms = 1e3 * (MPI_Wtime() - t0);
  report.free_solve_ms =
      report.total_ms - report.assembly_ms - report.fluid_weight_ms - report.qp_ms;
  // The whole field, for the output (outside the step's time) and the error indicator (in it).
  system_->place(q_, u, true);
  report.reduced = error_statement(u, inside);
  report.reduced["newton_iterations"] = report.newton_iterations;
  if (report.reduced.contains("indicator_ms"))
    report.total_ms += report.reduced["indicator_ms"].get<double>();
  outside_ += !inside;
  return report;
}

nlohmann::json ReducedController::error_statement(Vec u, bool inside) {
  const nlohmann::json& held = model_.report.at("held_back");
  nlohmann::json statement = {{"in_envelope", inside},
                              {"held_back_error_m", held.at("max_effector_error_m")},
                              {"indicator_m", nullptr},
                              {"estimated_error_m", nullptr}};
  if (!inside) return statement;  // outside the envelope no error is known
  statement["estimated_error_m"] = held.at("max_effector_error_m");
  if (!indicator_) return statement;
  const double t0 = MPI_Wtime();
  Eigen::VectorXd lambda(static_cast<Eigen::Index>(actuators_.size())), dx;
  for (size_t a = 0; a < actuators_.size(); ++a)
    lambda(static_cast<Eigen::Index>(a)) = constraints_[actuators_[a]].multiplier();
  if (indicator_->estimate(u, lambda, dx)) {
    const double indicator = ResidualErrorIndicator::largest_move(dx);
    statement["indicator_m"] = indicator;
    // The training's calibration: the largest ratio of the held-back samples' true error to
    // their indicator (a model trained before it had none: the held-back error stands). The
    // indicator's influence functions are the nearest training sample's, which on a finger
    // whose stiffness turns with the pressure miss some answers' error several times over
    // (docs/reduced_models.md): the held-back error stays a floor.
    const auto ratio = held.find("indicator_ratio_max");
    if (ratio != held.end() && ratio->is_number() && held.at("max_effector_error_m").is_number())
      statement["estimated_error_m"] = std::max(held.at("max_effector_error_m").get<double>(),
                                                std::max(1.0, ratio->get<double>()) * indicator);
  }
  indicator_s_ += MPI_Wtime() - t0;
  statement["indicator_ms"] = 1e3 * (MPI_Wtime() - t0);
  return statement;
}

nlohmann::json ReducedController::summary() const {
  return {{"file", path_},
          {"modes", system_->size()},
          {"elements", model_.elements.size()},
          {"patches", model_.patches.size()},
          {"sampled_dofs", system_->sampled_dofs()},
          {"steps_outside_envelope", outside_},
          {"error_indicator", indicator_
                                  ? nlohmann::json{{"setup_seconds", indicator_->setup_seconds()},
                                                   {"seconds", indicator_s_}}
                                  : nlohmann::json(nullptr)},
          {"training", model_.report}};
}

}  // namespace hs
