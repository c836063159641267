#include "solvers/reduced/training_stepper.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <sstream>

#include "common/error.hpp"
#include "common/exchange.hpp"
#include "common/interrupt.hpp"
#include "reduction/design.hpp"
#include "solvers/reduced/error_indicator.hpp"
#include "solvers/reduced/model_fit.hpp"
#include "solvers/reduced/offline.hpp"
#include "solvers/reduced/reduced_system.hpp"
#include "solvers/reduced/whole_body.hpp"

namespace hs {
TrainingStepper::TrainingStepper(const Config& config, Problem& problem, ConstraintSet& constraints,
                                 BorderedNewton& newton, SteppingStats& stats,
                                 const ResultRecorder& recorder)
    : config_(config),
      problem_(problem),
      constraints_(constraints),
      stats_(stats),
      states_(config, problem, constraints, newton, stats, recorder),
      effectors_(config, problem),
      controller_(config, problem, constraints, newton, effectors_) {
  check_reducible(config, problem, constraints);
  const auto& actuators = config.control->actuators;
  const int m = static_cast<int>(actuators.size()), n = config.training->samples;
  if (n < 3)
    throw InputError(config.deck_path + ": hydrosoft reduce: --samples must be at least 3");
  for (const auto& a : actuators)
    if (a.min_multiplier < -1e299 || a.max_multiplier > 1e299 ||
        a.min_multiplier >= a.max_multiplier)
      throw InputError(config.deck_path + ": control.actuators '" + a.constraint +
                       "': hydrosoft reduce samples each actuator between its min and max "
                       "pressure (or tension): both bounds are needed, min < max");
  if (config.training->design == TrainingDesignKind::grid) {
    int64_t total = 1;
    for (int a = 0; a < m; ++a) total *= n;
    if (total > 100000)
      throw InputError(config.deck_path + ": hydrosoft reduce: " + std::to_string(total) +
                       " samples (--samples " + std::to_string(n) + " per actuator, " +
                       std::to_string(m) + " actuators); at most 100000 (--design halton " +
                       "takes --samples in all)");
    planned_samples_ = static_cast<size_t>(total);
  } else {
    if (m > 10 || n < (1 << m) + 4)
      throw InputError(
          config.deck_path + ": hydrosoft reduce --design halton: " + std::to_string(m) +
          " actuators need --samples of at least " + std::to_string((1 << std::min(m, 10)) + 4) +
          " (the 2^m corners of their box and 4 more)" + (m > 10 ? "; at most 10 actuators" : ""));
    planned_samples_ = static_cast<size_t>(n);
  }
}

void TrainingStepper::plan() {
  const auto& actuators = config_.control->actuators;
  const int m = static_cast<int>(actuators.size()), n = config_.training->samples;
  std::vector<double> rest(m);  // the rest actuation in the unit box
  for (int a = 0; a < m; ++a) {
    const auto& b = actuators[a];
    const double lambda = constraints_[constraints_.find(b.constraint)].multiplier();
    rest[a] =
        std::clamp((lambda - b.min_multiplier) / (b.max_multiplier - b.min_multiplier), 0.0, 1.0);
  }
  const TrainingDesign design = config_.training->design == TrainingDesignKind::grid
                                    ? grid_design(m, n)
                                    : halton_design(m, n, rest);
  for (const auto& x : design.points) {
    std::vector<double> lambda(m);
    for (int a = 0; a < m; ++a) {
      const auto& b = actuators[a];
      lambda[a] = b.min_multiplier + (b.max_multiplier - b.min_multiplier) * x[a];
    }
    samples_.push_back(lambda);
  }
  held_back_ = design.held_back;
}

int TrainingStepper::planned_steps() const {
  return phase() == 0 ? states_.planned_steps() : static_cast<int>(planned_samples_);
}

void TrainingStepper::resume(const Restart&, Vec) {
  throw InputError("--restart: hydrosoft reduce starts afresh");
}

std::optional<StepReport> TrainingStepper::advance(Vec u) {
  if (!states_.done()) return states_.advance(u);
  if (!started_) {
    t_start_ = MPI_Wtime();
    plan();
    controller_.set_rest(u);
    snapshots_.push_back(local_values(u));
    positions_.push_back(effectors_.positions(u));
    started_ = true;
  }
  const auto& actuators = config_.control->actuators;
  const std::vector<double>& lambda = samples_[next_];
  for (size_t a = 0; a < actuators.size(); ++a)
    constraints_[constraints_.find(actuators[a].constraint)].prescribe(
        Constraint::Control::multiplier, lambda[a]);
  ControlStepReport r;
  controller_.settle(u, r);  // throws SolveError when no equilibrium is found
  iterations_ += r.newton_iterations;
  if (r.limit_point)
    throw SolveError("hydrosoft reduce: no equilibrium at sample " + std::to_string(next_ + 1) +
                     " (a limit point of the pressure): narrow the actuators' ranges");
  snapshots_.push_back(local_values(u));
  positions_.push_back(effectors_.positions(u));
  ++next_;
  StepReport step;
  step.index = static_cast<int>(next_);
  std::ostringstream what;
  what << "sample" << (held_back_[next_ - 1] ? " (held back)" : "");
  for (double l : lambda) what << " " << l;
  step.what = what.str();
  step.time = static_cast<double>(states_.states().size()) + static_cast<double>(next_);
  step.time_kind = "sample";
  step.output = next_ == samples_.size();
  if (next_ == samples_.size()) build();
  return step;
}

void TrainingStepper::build() {
  snapshot_seconds_ = MPI_Wtime() - t_start_;
  if (problem_.distribution().size == 1) {
    report_ = build_on(problem_, constraints_, effectors_, snapshots_);
  } else {
    report_ = build_on_rank_zero();
  }
  report_["file"] = config_.training->output;
  built_ = true;
}

// Several ranks: the snapshots and the constraints' states go to rank 0, which builds, checks
// and writes the model on the whole body (whole_body.hpp); every rank gets the report.
nlohmann::json TrainingStepper::build_on_rank_zero() {
  const MPI_Comm comm = problem_.comm();
  const std::vector<Eigen::VectorXd> snapshots = gather_in_mesh_order(problem_, snapshots_);
  const std::vector<Constraint::State> states = constraints_.snapshot();
  std::string report;
  on_rank_zero(comm, [&] {
    try {
      const WholeBody body(config_, states);
      report =
          build_on(*body.problem, *body.constraints, *body.effectors, body.local_order(snapshots))
              .dump();
    } catch (const Interrupted&) {  // every rank got the signal: they stop below, together
    }
  });
  stop_if_interrupted(comm);
  broadcast_string(report, 0, comm);
  return nlohmann::json::parse(report);
}

// The model from the snapshots (in `problem`'s local dofs), its check on the held-back
// samples, the file; the training's report.
nlohmann::json TrainingStepper::build_on(Problem& problem, ConstraintSet& constraints,
                                         const Effectors& effectors,
                                         const std::vector<Eigen::VectorXd>& snapshots) {
  std::vector<int> train, check;
  train.push_back(0);  // the rest state
  for (size_t s = 0; s < samples_.size(); ++s) (held_back_[s] ? check : train).push_back(s + 1);
  Eigen::MatrixXd training(snapshots[0].size(), train.size());
  for (size_t i = 0; i < train.size(); ++i) training.col(i) = snapshots[train[i]];
  ReducedModel model;
  model.deck = config_.deck_name;
  model.physics = reduced_physics(config_);
  record_mesh(problem, model);
  for (const auto& a : config_.control->actuators) {
    model.actuators.push_back(a.constraint);
    model.lower.push_back(a.min_multiplier);
    model.upper.push_back(a.max_multiplier);
  }
  build_reduced_model(problem, training, *config_.training, model);
  const Eigen::MatrixXd phi = [&] {  // the basis in local order again
    Eigen::MatrixXd local(model.basis.rows(), model.basis.cols());
    const Distribution& dist = problem.distribution();
    for (int64_t n = 0; n < dist.num_local(); ++n)
      local.middleRows(3 * n, 3) = model.basis.middleRows(3 * dist.old_of_local[n], 3);
    return local;
  }();
  model.training_actuations.resize(train.size() - 1, model.actuators.size());
  model.training_states.resize(train.size() - 1, phi.cols());
  for (size_t i = 1; i < train.size(); ++i) {
    for (size_t a = 0; a < model.actuators.size(); ++a)
      model.training_actuations(i - 1, a) = samples_[train[i] - 1][a];
    model.training_states.row(i - 1) = (phi.transpose() * snapshots[train[i]]).transpose();
  }

  check_held_back(problem, constraints, effectors, snapshots, check, model);
  model.report["samples"] = samples_.size();
  model.report["training_samples"] = train.size() - 1;
  model.report["snapshot_seconds"] = snapshot_seconds_;
  model.report["seconds"] = MPI_Wtime() - t_start_;
  write_reduced_model(config_.training->output, model);
  return model.report;
}

// The held-back samples: the reduced equilibrium at each, from its nearest training
// neighbour's projection, against the full model's; the errors go to model.report.
void TrainingStepper::check_held_back(Problem& problem, ConstraintSet& constraints,
                                      const Effectors& effectors,
                                      const std::vector<Eigen::VectorXd>& snapshots,
                                      const std::vector<int>& check, ReducedModel& model) {
  const double t_check = MPI_Wtime();
  const std::vector<Constraint::State> saved = constraints.snapshot();
  std::vector<Vec> rows;
  for (int e = 0; e < effectors.size(); ++e)
    for (int d = 0; d < 3; ++d) rows.push_back(effectors.row(e, d));
  model.report["held_back"] = {{"samples", check.size()}};
  ReducedSystem system(config_, problem, constraints, model, config_.training->output, rows);
  std::vector<int> actuators;
  for (const std::string& name : model.actuators) actuators.push_back(constraints.find(name));
  ResidualErrorIndicator indicator(problem, constraints, system, actuators, rows);
  VecHandle x(problem.create_vector());
  double max_error = 0, sum_error = 0, max_field = 0;
  // The residual indicator's calibration: the largest ratio of a sample's error to its
  // indicator, and the smallest (how far the indicator overstates).
  double ratio_max = 0, ratio_min = HUGE_VAL;
  nlohmann::json unsolved = nlohmann::json::array();
  for (int h : check) {
    if (const int signal = interrupt_signal()) throw Interrupted(signal);
    const Eigen::VectorXd lambda =
        Eigen::Map<const Eigen::VectorXd>(samples_[h - 1].data(), model.actuators.size());
    HS_PETSC(VecSet(x, 0.0));
    Eigen::VectorXd q;
    if (!system.solve_at(lambda, q, x).converged) {  // the model is too coarse there
      unsolved.push_back(samples_[h - 1]);
      continue;
    }
    system.place(q, x, true);
    const std::vector<double> reduced = effectors.positions(x);
    double error = 0;
    for (size_t i = 0; i + 2 < reduced.size(); i += 3) {
      double d2 = 0;
      for (int d = 0; d < 3; ++d) d2 += std::pow(reduced[i + d] - positions_[h][i + d], 2);
      error = std::max(error, std::sqrt(d2));
    }
    Eigen::VectorXd dx;
    if (indicator.estimate(x, lambda, dx)) {
      const double estimate = ResidualErrorIndicator::largest_move(dx);
      if (estimate > 0) {
        ratio_max = std::max(ratio_max, error / estimate);
        ratio_min = std::min(ratio_min, error / estimate);
      }
    }
    const Eigen::VectorXd& full = snapshots[h];
    max_error = std::max(max_error, error);
    sum_error += error;
    max_field =
        std::max(max_field, (local_values(x) - full).norm() / std::max(full.norm(), 1e-300));
  }
  constraints.restore(saved);
  // An unsolved sample leaves the error near it unknown: no error is stated then (every
  // answer's estimate is null), rather than the solved samples' smaller one.
  const size_t solved = check.size() - unsolved.size();
  const auto stated = [&](double value) {
    return unsolved.empty() ? nlohmann::json(value) : nlohmann::json(nullptr);
  };
  model.report["held_back"] = {
      {"samples", check.size()},
      {"max_effector_error_m", stated(max_error)},
      {"mean_effector_error_m", stated(solved > 0 ? sum_error / solved : 0.0)},
      {"max_field_error", stated(max_field)},
      {"indicator_ratio_max", ratio_max > 0 ? stated(ratio_max) : nlohmann::json(nullptr)},
      {"indicator_ratio_min", ratio_max > 0 ? stated(ratio_min) : nlohmann::json(nullptr)},
      {"indicator_setup_seconds", indicator.setup_seconds()},
      {"unsolved", unsolved.size()},
      {"unsolved_actuations", unsolved},
      {"seconds", MPI_Wtime() - t_check}};
  if (!unsolved.empty())  // on one rank
    std::cerr << "hydrosoft: warning: the reduced model found no equilibrium at " << unsolved.size()
              << " of its " << check.size() << " held-back samples (actuations " << unsolved.dump()
              << "), so it states no error: train with more --samples, or narrow the actuators' "
                 "ranges away from there\n";
}

void TrainingStepper::add_summary(nlohmann::json& summary) const {
  states_.add_summary(summary);
  summary["reduction"] = report_;
}

}  // namespace hs
