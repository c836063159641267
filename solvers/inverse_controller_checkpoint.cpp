// InverseController, its state at a target-set boundary for checkpoints and restarts
// (docs/control.md, "Checkpoints and restarts").
#include "common/error.hpp"
#include "solvers/inverse_controller.hpp"

namespace hs {

// Only a checkpointing run that keeps a factorization in line across steps needs to know
// where it was made; the background mode's preconditioner is whatever a thread finished,
// which no run can repeat (a restart factors in line at its first step).
bool InverseController::keeps_factorization() const {
  return config_.output.checkpoint && config_.control->refactor_every > 1 && !background_ &&
         config_.control->free_solve == FreeSolve::one_step;
}

nlohmann::json InverseController::checkpoint_state() const {
  nlohmann::json s;
  s["rest_measures"] = nlohmann::json::array();
  for (const auto& a : actuators_) s["rest_measures"].push_back(a.rest_measure);
  s["last_pressures"] = last_pressures_;
  s["step_count"] = step_count_;
  s["factored"] = factored_;
  s["steps_since_factorization"] = steps_since_factorization_;
  s["residual_at_factorization"] = residual_at_factorization_;
  if (step_start_) s["step_start_pressures"] = step_start_pressures_;
  if (keeps_factorization() && factored_) s["factored_constraints"] = factored_constraints_;
  return s;
}

NamedVecs InverseController::checkpoint_fields() const {
  NamedVecs fields{{"control_last_free", last_free_}};
  if (step_start_) fields.emplace_back("control_step_start", step_start_);
  if (keeps_factorization() && factored_) fields.emplace_back("control_factored_at", factored_at_);
  return fields;
}

void InverseController::resume(const nlohmann::json& s, const Restart& restart) {
  const auto& rest = s.at("rest_measures");
  if (rest.size() != actuators_.size())
    throw InputError("--restart: the checkpoint's controller has " + std::to_string(rest.size()) +
                     " actuators, this deck's " + std::to_string(actuators_.size()));
  for (size_t a = 0; a < actuators_.size(); ++a) actuators_[a].rest_measure = rest[a];
  last_pressures_ = s.at("last_pressures").get<std::vector<double>>();
  if (!last_free_) last_free_ = VecHandle(problem_.create_vector());
  restart.read("control_last_free", problem_, last_free_);
  step_count_ = s.at("step_count");
  factored_ = s.at("factored");
  steps_since_factorization_ = s.at("steps_since_factorization");
  residual_at_factorization_ = s.at("residual_at_factorization");
  force_refactor_ = retake_converged_ = false;
  if (s.contains("step_start_pressures")) {
    step_start_pressures_ = s.at("step_start_pressures").get<std::vector<double>>();
    if (!step_start_) step_start_ = VecHandle(problem_.create_vector());
    restart.read("control_step_start", problem_, step_start_);
  }
  if (!s.contains("factored_constraints")) return;
  // The kept factorization, made again as the step that made it did: the residual, then the
  // tangent, at that step's configuration and constraint states; the states of now after.
  factored_constraints_ = s.at("factored_constraints");
  if (!factored_at_) factored_at_ = VecHandle(problem_.create_vector());
  restart.read("control_factored_at", problem_, factored_at_);
  const nlohmann::json now = constraint_states(constraints_);
  restore_constraint_states(constraints_, factored_constraints_);
  problem_.apply_dirichlet(factored_at_, 1.0);
  std::vector<double> controls;
  if (!constraints_.residual(factored_at_, 1.0, R_, controls) ||
      !constraints_.linearize(factored_at_, 1.0, J_, lin_))
    throw SolveError("--restart: an element is inverted where the kept factorization was made");
  HS_PETSC(KSPSetOperators(ksp_, J_, J_));
  const OptionsScope scope(options_.database());  // its factor's options
  HS_PETSC(KSPSetUp(ksp_));
  if (!factor_responses(ksp_))
    throw SolveError("--restart: the factorization of the kept tangent failed");
  restore_constraint_states(constraints_, now);
}

}  // namespace hs
