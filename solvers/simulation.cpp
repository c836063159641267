#include "solvers/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <utility>

#include "common/error.hpp"
#include "common/interrupt.hpp"
#include "solvers/progress.hpp"
#include "solvers/run_output.hpp"
#include "solvers/run_setup.hpp"
#include "solvers/stepping/stepper.hpp"
#include "solvers/verification/error_norms.hpp"

namespace hs {
namespace {

// The summary of a run that ended: the set-up's keys, the energy of a dynamic run, the errors
// against the exact solution, the verification quantities, and the stepper's own keys.
// load_factor: that of the last step (the final state's reactions are taken at it).
nlohmann::json final_summary(RunSetup& run, const Stepper& stepper, const nlohmann::json& history,
                             double load_factor) {
  nlohmann::json summary = run.summary();
  const SteppingStats& stats = run.stats;
  if (!stats.energy.empty()) {
    // Drift of the total energy relative to the largest stored energy reached.
    double drift = 0;
    for (double e : stats.energy) drift = std::max(drift, std::abs(e - stats.energy.front()));
    summary["energy"]["initial"] = stats.energy.front();
    summary["energy"]["final"] = stats.energy.back();
    summary["energy"]["max_drift"] = drift;
    summary["energy"]["max_stored"] = stats.max_stored_energy;
  }
  if (run.exact) {
    const ErrorNorms e =
        displacement_error(*run.problem, run.u, *run.exact, stepper.final_load_factor());
    summary["error"]["l2_relative"] = e.l2_relative;
    summary["error"]["l2_absolute"] = e.l2_absolute;
    if (run.exact->has_pressure()) {
      const ErrorNorms p = pressure_error(*run.problem, run.u, *run.exact);
      summary["error"]["pressure_l2_relative"] = p.l2_relative;
      summary["error"]["pressure_l2_absolute"] = p.l2_absolute;
    }
  }
  if (!history.empty()) {
    summary["verification"] = history.back();
    summary["verification"]["steps"] = history;
  }
  if (!run.problem->reaction_groups().empty())
    summary["reactions_N"] = reactions_json(*run.problem, run.u, load_factor);
  if (run.problem->has_contact())
    summary["contact"] = contact_json(*run.problem, run.u, load_factor);
  stepper.add_summary(summary);
  // The obstacles' forces beside the constraints' in the run's end state, in any kind of run.
  if (run.problem->contact()) summary["end_of_run"]["contact"] = summary["contact"]["obstacles"];
  summary["time_s"]["total"] = MPI_Wtime() - run.t_start;
  return summary;
}

}  // namespace

nlohmann::json run_simulation(const Config& config, MPI_Comm comm, InteractiveIo io,
                              const std::string& restart_folder) {
  RunSetup run(config, comm, restart_folder);
  Problem& problem = *run.problem;
  ResultRecorder& recorder = *run.recorder;
  const std::unique_ptr<Stepper> stepper = make_stepper(run.stepper_parts(), std::move(io));
  if (run.constraints) recorder.set_constraints(run.constraints.get());
  HistorySources sources =
      history_sources(config, has_constraints(run.kind), run.constraints.get(), run.stats);
  stepper->add_history(sources);
  recorder.set_history(std::move(sources));
  const bool verifies = stepper->verifies();
  nlohmann::json history;  // verification quantities after every load step
  double load_factor = stepper->final_load_factor();  // of u, once a step was taken
  if (verifies) history = nlohmann::json::array();
  try {
    // A signal during the set-up stops the run here, before any step (nothing to keep).
    stop_if_interrupted(comm);
    if (run.restart) {
      stepper->resume(*run.restart, run.u);
      if (problem.has_nodal_volume_multipliers()) {
        const VecHandle lambda(problem.create_vector());
        run.restart->read(kVolumeMultiplierField, problem, lambda);
        problem.set_volume_multipliers(lambda);
      }
      if (problem.has_fbar_volume_multipliers()) {
        // A checkpoint of an older run has none: the solves raise them again.
        const std::vector<double> lambda =
            run.restart->read_elements(kFbarMultiplierField, problem);
        if (!lambda.empty()) problem.set_fbar_volume_multipliers(lambda);
      }
      if (verifies) history = run.restart->position().at("verification");
    } else if (const auto rest = stepper->initial_output()) {
      recorder.record(rest->time, run.u, rest->load_factor, rest->time_kind);
    }
    std::optional<Progress> progress;
    std::optional<StepReport> unwritten;  // the last step taken, when not written
    for (int phase = -1; !stepper->done();) {
      if (stepper->phase() != phase) {  // the progress and the checkpoints count anew
        phase = stepper->phase();
        progress.emplace(config.output.progress, comm, stepper->planned_steps());
        run.checkpoints->start_count();
      }
      const std::optional<StepReport> step = stepper->advance(run.u);
      if (!step) continue;
      load_factor = step->load_factor;
      if (stepper->planned_steps() > 0)
        progress->step(step->index, step->what, stepper->newton_iterations(), run.stats.cutbacks);
      if (verifies && run.exact) {
        const auto v = verification_quantities(*run.exact, problem, run.u, step->load_factor);
        if (!v.is_null()) history.push_back(v);
      }
      // A signal stops the run at this step boundary, the step written first.
      const int signal = interrupt_requested(comm);
      unwritten = step;
      if (step->output || signal) {
        stepper->number_output(recorder.written());
        recorder.record(step->time, run.u, step->load_factor, step->time_kind);
        unwritten.reset();
      }
      if (run.checkpoints->due(signal)) {
        nlohmann::json position = stepper->position();
        if (verifies) position["verification"] = history;
        NamedVecs fields = stepper->checkpoint_fields(run.u);
        const VecHandle lambda(problem.create_vector());
        if (problem.has_nodal_volume_multipliers()) {
          problem.volume_multiplier_field(lambda);
          fields.emplace_back(kVolumeMultiplierField, lambda);
        }
        NamedValues element_fields;
        if (problem.has_fbar_volume_multipliers())
          element_fields.emplace_back(kFbarMultiplierField, problem.fbar_volume_multipliers());
        run.checkpoints->write(position, fields, stepper->checkpoint_series(), element_fields);
      }
      if (signal) throw Interrupted(signal);
    }
    if (unwritten) {  // the last step always (an interactive run's end is not known ahead)
      stepper->number_output(recorder.written());
      recorder.record(unwritten->time, run.u, unwritten->load_factor, unwritten->time_kind);
    }
  } catch (SolveError& e) {
    // Every rank is here together (a failed solve, an inverted element, a refused step and a
    // signal are all decided collectively): the converged steps go to "<folder>.failed".
    nlohmann::json summary = run.summary();
    stepper->add_failed_summary(summary);
    keep_converged_steps(e, recorder, std::move(summary), comm);
    throw;
  }
  nlohmann::json summary = final_summary(run, *stepper, history, load_factor);
  const std::string folder = recorder.finish(summary);  // adds "status": "ok"
  summary["output"]["folder"] = folder;
  return summary;
}

}  // namespace hs
