#include "solvers/stepping/control_stepper.hpp"

#include <utility>

namespace hs {

ControlStepper::ControlStepper(const Config& config, Problem& problem, ConstraintSet& constraints,
                               BorderedNewton& newton, SteppingStats& stats,
                               const ResultRecorder& recorder, InteractiveIo io)
    : stats_(stats),
      every_(config.output.every),
      states_(config, problem, constraints, newton, stats, recorder),
      loop_(config, problem, constraints, newton, std::move(io)) {}

int ControlStepper::planned_steps() const {
  return phase() == 0 ? states_.planned_steps() : loop_.planned_sets();
}

std::optional<StepReport> ControlStepper::advance(Vec u) {
  if (!states_.done()) return states_.advance(u);
  if (!started_) {
    loop_.start(u);
    started_ = true;
  }
  if (!loop_.next_set(u)) return std::nullopt;
  StepReport step;
  step.index = loop_.sets_done();
  if (loop_.planned_sets() > 0) step.what = loop_.progress_text();
  step.time = static_cast<double>(states_.states().size()) + loop_.sets_done();
  step.time_kind = "target_set";
  step.output = loop_.sets_done() % every_ == 0 || loop_.done();
  if (!step.output) loop_.answer(-1);
  return step;
}

void ControlStepper::number_output(int step) {
  if (phase() == 1) loop_.answer(step);
}

nlohmann::json ControlStepper::position() const {
  return phase() == 0 ? states_.position() : loop_.position(states_.states());
}

NamedVecs ControlStepper::checkpoint_fields(Vec u) const {
  return phase() == 0 ? states_.checkpoint_fields(u) : loop_.checkpoint_fields(u);
}

void ControlStepper::resume(const Restart& restart, Vec u) {
  if (ControlLoop::resumes(restart))
    states_.resume_done(loop_.resume(restart, u));
  else
    states_.resume(restart, u);
}

int ControlStepper::newton_iterations() const {
  return phase() == 0 ? states_.newton_iterations() : loop_.newton_iterations();
}

void ControlStepper::add_history(HistorySources& sources) const {
  const ControlLoop* loop = &loop_;
  const SteppingStats* stats = &stats_;
  sources.newton_iterations = [stats, loop] {
    return stats->newton_iterations + loop->newton_iterations();
  };
  sources.columns.push_back([loop](Vec u, HistoryRow& row) { loop->add_history(u, row); });
}

void ControlStepper::add_summary(nlohmann::json& summary) const {
  states_.add_summary(summary);
  const nlohmann::json control = loop_.summary();
  for (const auto& [key, value] : control.items()) summary[key] = value;
}

void ControlStepper::add_failed_summary(nlohmann::json& summary) const {
  summary["targets"] = loop_.targets_so_far();
}

}  // namespace hs
