#include "solvers/simulation.hpp"

#include <petscsys.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <utility>

#include "common/deck_reader.hpp"
#include "common/error.hpp"
#include "common/interrupt.hpp"
#include "deck/boundary_conflicts.hpp"
#include "deck/deck.hpp"
#include "deck/exact_section.hpp"
#include "io/output.hpp"
#include "mesh/distribution.hpp"
#include "mesh/rigid_motions.hpp"
#include "solvers/checkpoint.hpp"
#include "solvers/control_run.hpp"
#include "solvers/distributed_mesh.hpp"
#include "solvers/newton_solver.hpp"
#include "solvers/output/result_recorder.hpp"
#include "solvers/problem.hpp"
#include "solvers/progress.hpp"
#include "solvers/run_output.hpp"
#include "solvers/state_stepping.hpp"
#include "solvers/stepping.hpp"
#include "solvers/verification/error_norms.hpp"
#include "solvers/verification/reference_check.hpp"

namespace hs {

nlohmann::json run_simulation(const Config& config, MPI_Comm comm, InteractiveIo io,
                              const std::string& restart_folder) {
  const double t_start = MPI_Wtime();
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);

  check_solver_types(config.solver, config.deck_path);
  // A static body that its conditions leave free to move rigidly has a singular tangent:
  // every step would fail, which is better said at once (again with the mesh, below).
  if (config.dirichlet.empty())
    check_rigid_motions_held(config, std::map<std::string, std::vector<int32_t>>{}, {}, comm);
  // The checkpoint to continue from is opened and checked first: the output folder, opened
  // next, may be the very folder it lies in (its .partial is cleared then).
  check_checkpoint_use(config, !restart_folder.empty());
  std::unique_ptr<Restart> restart;
  if (!restart_folder.empty()) restart = std::make_unique<Restart>(restart_folder, config, comm);
  // First, before any work: a second run on the same output folder stops here, at once.
  auto output_folder = open_output_folder(config.output.folder, comm);
  MeshLoadTimes mesh_times;
  const Distribution dist = load_distributed_mesh(config.mesh, comm, &mesh_times);
  check_groups(config, dist.groups);
  check_rigid_motions_held(config, dist.node_groups, dist.x, comm);
  // The deck's exact solution, if any: the values of Dirichlet conditions marked exact, and
  // the reference of the errors and verification quantities reported below.
  const auto exact_solution = make_exact_solution(config);
  const ExactSolution* exact = exact_solution.get();
  if (exact) check_reference_finite(config, *exact, dist.x, comm);
  ExactDirichlet exact_dirichlet;
  if (exact)
    exact_dirichlet = [exact](const std::array<double, 3>& X, double s) {
      return exact->displacement(X, s);
    };
  // Two entries that prescribe one node's component differently: refused before any solve.
  // Every rank knows all the groups of its nodes, ghosts included, so each conflict is seen.
  check_boundary_conflicts(config, dist.node_groups, dist.x, dist.num_owned(), exact_dirichlet,
                           comm);
  Problem problem(config, dist, comm, exact_dirichlet);
  if (restart) restart->check_mesh(problem);
  // A scene with cavities or states runs the bordered Newton (displacements and cavity
  // pressures); any other the plain SNES. No cavity code runs in a scene without cavities.
  const bool staged = !config.cavities.empty() || !config.cables.empty() ||
                      !config.states.empty() || config.tip || config.control;
  std::unique_ptr<ConstraintSet> constraints;
  if (staged) constraints = std::make_unique<ConstraintSet>(config, problem);
  // Symmetric unless the deck puts a follower pressure on an open surface or a constraint's
  // forces are no gradient (a cable with friction). Definite (CG) only for linear laws without
  // any pressure stiffness (a cavity's can make the tangent indefinite near a limit point).
  bool linear_laws = true;
  for (const auto& m : config.materials) linear_laws &= m.law->tangent_always_definite();
  set_solver_options(
      config.solver,
      !problem.has_open_surface_pressure() && (!constraints || constraints->symmetric()),
      linear_laws && !problem.has_follower_loads());
  std::unique_ptr<NewtonSolver> newton;
  std::unique_ptr<BorderedNewton> bordered;
  if (staged)
    bordered = std::make_unique<BorderedNewton>(problem, *constraints);
  else
    newton = std::make_unique<NewtonSolver>(problem);
  ResultRecorder recorder(problem, config, std::move(output_folder), comm);
  const double t_setup = MPI_Wtime() - t_start;

  // Owned: an input error found after this point (a cavity volume that cannot exist, a control
  // target out of reach) leaves the caller's process going.
  const VecHandle u(problem.create_vector());
  {
    VecHandle f;
    HS_PETSC(VecDuplicate(u, f.out()));
    problem.external_load(u, 1.0, f);
    PetscReal norm = 0;
    HS_PETSC(VecNorm(f, NORM_2, &norm));
    if (newton) newton->scale_absolute_tolerance(norm);
    if (bordered) bordered->set_load_norm(norm);
  }
  SteppingStats stats;
  Checkpointer checkpoints(config, problem, stats, recorder.staging(), comm);
  if (restart) {
    restart->restore(stats);
    recorder.set_newton_before(stats.newton_iterations);
  }
  double final_load = 1.0;
  nlohmann::json history;  // verification quantities after every load step
  auto output_due = [&](int k, int last) { return k == last || (k % config.output.every) == 0; };

  StateRun state_run;
  nlohmann::json control;
  std::unique_ptr<ControlLoop> control_loop;
  if (config.control)
    control_loop =
        std::make_unique<ControlLoop>(config, problem, *constraints, *bordered, std::move(io));
  if (constraints) recorder.set_constraints(constraints.get());
  recorder.set_history(
      history_sources(config, staged, constraints.get(), control_loop.get(), stats));

  // The summary's keys that any run has, ended or failed: sizes, counts, timings.
  auto run_summary = [&] {
    nlohmann::json summary;
    summary["deck"] = config.deck_path;
    summary["ranks"] = size;
    summary["dofs"] = problem.num_global_dofs();
    summary["nodes"] = dist.num_global();
    summary["elements"] = dist.num_global_tets;
    summary["order"] = dist.order;
    summary["steps"] = stats.steps;
    summary["cutbacks"] = stats.cutbacks;
    summary["newton_iterations"] = stats.newton_iterations;
    summary["linear_iterations"] = stats.linear_iterations;
    summary["outputs"] = recorder.written();
    add_timings(summary, problem, dist, mesh_times, recorder, comm);
    summary["time_s"]["setup"] = t_setup;
    double solve = newton ? newton->solve_seconds() : bordered->solve_seconds();
    MPI_Allreduce(MPI_IN_PLACE, &solve, 1, MPI_DOUBLE, MPI_MAX, comm);
    summary["time_s"]["solve"] = solve;
    if (staged) {
      summary["parts"] = constraints->parts();
      double fluid = constraints->fluid_weight_seconds(),
             constraint = bordered->constraint_seconds();
      MPI_Allreduce(MPI_IN_PLACE, &fluid, 1, MPI_DOUBLE, MPI_MAX, comm);
      MPI_Allreduce(MPI_IN_PLACE, &constraint, 1, MPI_DOUBLE, MPI_MAX, comm);
      summary["time_s"]["fluid_weight"] = fluid;
      summary["time_s"]["constraint"] = constraint;
      double build = constraints->constraint_build_seconds();
      MPI_Allreduce(MPI_IN_PLACE, &build, 1, MPI_DOUBLE, MPI_MAX, comm);
      summary["time_s"]["constraint_build"] = build;
    } else {
      summary["parts"] = {
          {"cavities", 0},
          {"cables", 0},
          {"fluid_weight", {{"cavities", 0}, {"device", "none"}, {"method", "none"}}},
          {"cuda_context", false}};
    }
    summary["output"]["xdmf"] = recorder.xdmf_path();
    if (restart) summary["restarted_from"] = restart->summary();
    summary["time_s"]["total"] = MPI_Wtime() - t_start;
    return summary;
  };

  try {
    // A signal during the set-up stops the run here, before any step (nothing to keep).
    stop_if_interrupted(comm);
    if (staged) {
      // A control deck's checkpoint is of its states or of its target sets.
      if (restart && control_loop && ControlLoop::resumes(*restart))
        state_run.states = control_loop->resume(*restart, u);
      else
        state_run = run_states(config, problem, *constraints, *bordered, recorder, u, stats, comm,
                               checkpoints, restart.get());
      if (control_loop)
        control = control_loop->run(u, recorder, static_cast<double>(state_run.states.size()),
                                    &checkpoints, state_run.states);
    } else if (config.time.type == TimeType::dynamic) {
      const int nsteps = static_cast<int>(std::ceil(config.time.end_time / config.time.dt - 1e-9));
      DynamicResume resume;
      if (restart) {
        resume.step = restart->position().at("step");
        restart->read("displacement", problem, u);
        resume.fill = [&](Vec v, Vec a) {
          restart->read("velocity", problem, v);
          restart->read("acceleration", problem, a);
        };
        stats.energy = restart->series("energy");
      } else {
        recorder.record(0.0, u, 1.0);
      }
      Progress progress(config.output.progress, comm, nsteps);
      auto on_step = [&](int n, double t, Vec un, Vec v, Vec a) {
        progress.step(n, "time " + format_number(t) + " s", stats.newton_iterations);
        // A signal stops the run at this step boundary, the step written first.
        const int signal = interrupt_requested(comm);
        if (output_due(n, nsteps) || signal) recorder.record(t, un, 1.0);
        if (checkpoints.due(signal))
          checkpoints.write(
              {{"step", n}, {"time", t}, {"dt", config.time.dt}, {"last", n == nsteps}},
              {{"displacement", un}, {"velocity", v}, {"acceleration", a}},
              {{"energy", stats.energy}});
        if (signal) throw Interrupted(signal);
      };
      run_dynamic(problem, *newton, config.time, u, stats, on_step, restart ? &resume : nullptr);
    } else {
      const auto schedule = load_schedule(config.time);
      history = nlohmann::json::array();
      LoadStepper stepper(problem, *newton, config.time.max_cutbacks);
      size_t first = 0;
      if (restart) {
        const nlohmann::json& p = restart->position();
        first = p.at("step");
        restart->read("displacement", problem, u);
        restart->read("previous_displacement", problem, stepper.previous());
        stepper.resume(p.at("load_factor"), p.at("previous_load_factor"), p.at("has_previous"));
        history = p.at("verification");
      }
      stats.max_steps = max_substeps(static_cast<int64_t>(schedule.size()));
      Progress progress(config.output.progress, comm, static_cast<int>(schedule.size()));
      for (size_t k = first; k < schedule.size(); ++k) {
        stepper.advance(u, schedule[k], static_cast<int>(k + 1), stats);
        progress.step(static_cast<int>(k + 1), "load " + format_number(schedule[k]),
                      stats.newton_iterations);
        if (exact) {
          const auto v = verification_quantities(*exact, problem, u, schedule[k]);
          if (!v.is_null()) history.push_back(v);
        }
        const int signal = interrupt_requested(comm);
        if (output_due(static_cast<int>(k + 1), static_cast<int>(schedule.size())) || signal)
          recorder.record(schedule[k], u, schedule[k]);
        if (checkpoints.due(signal))
          checkpoints.write({{"step", k + 1},
                             {"load_factor", stepper.load_factor()},
                             {"previous_load_factor", stepper.previous_load_factor()},
                             {"has_previous", stepper.has_previous()},
                             {"verification", history},
                             {"last", k + 1 == schedule.size()}},
                            {{"displacement", u}, {"previous_displacement", stepper.previous()}});
        if (signal) throw Interrupted(signal);
      }
      final_load = schedule.back();
    }
  } catch (SolveError& e) {
    // Every rank is here together (a failed solve, an inverted element, a refused step and a
    // signal are all decided collectively): the converged steps go to "<folder>.failed".
    nlohmann::json summary = run_summary();
    if (control_loop) summary["targets"] = control_loop->targets_so_far();
    keep_converged_steps(e, recorder, std::move(summary), comm);
    throw;
  }

  nlohmann::json summary = run_summary();
  if (!stats.energy.empty()) {
    // Drift of the total energy relative to the largest stored energy reached.
    double drift = 0;
    for (double e : stats.energy) drift = std::max(drift, std::abs(e - stats.energy.front()));
    summary["energy"]["initial"] = stats.energy.front();
    summary["energy"]["final"] = stats.energy.back();
    summary["energy"]["max_drift"] = drift;
    summary["energy"]["max_stored"] = stats.max_stored_energy;
  }
  if (exact) {
    const ErrorNorms e = displacement_error(problem, u, *exact, final_load);
    summary["error"]["l2_relative"] = e.l2_relative;
    summary["error"]["l2_absolute"] = e.l2_absolute;
  }
  if (!history.empty()) {
    summary["verification"] = history.back();
    summary["verification"]["steps"] = history;
  }
  if (staged) {
    summary["states"] = state_run.states;
    for (const auto& [key, value] : control.items()) summary[key] = value;
    // After the last state, or in a control run after its last target set.
    summary["end_of_run"] = constraints->report();
  }
  summary["time_s"]["total"] = MPI_Wtime() - t_start;
  const std::string folder = recorder.finish(summary);  // adds "status": "ok"
  summary["output"]["folder"] = folder;
  return summary;
}

}  // namespace hs
