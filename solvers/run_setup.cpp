#include "solvers/run_setup.hpp"

#include <petscsys.h>

#include <map>
#include <vector>

#include "deck/boundary_conflicts.hpp"
#include "deck/deck.hpp"
#include "deck/exact_section.hpp"
#include "mesh/rigid_motions.hpp"
#include "solvers/incompressibility.hpp"
#include "solvers/run_output.hpp"
#include "solvers/verification/reference_check.hpp"

namespace hs {

RunSetup::RunSetup(const Config& config_in, MPI_Comm comm_in, const std::string& restart_folder)
    : config(config_in), comm(comm_in), t_start(MPI_Wtime()), kind(stepping_kind_of(config_in)) {
  check_solver_options(config.solver, config.deck_path);
  // A static body that its conditions leave free to move rigidly has a singular tangent:
  // every step would fail, which is better said at once (again with the mesh, below).
  if (config.dirichlet.empty())
    check_rigid_motions_held(config, std::map<std::string, std::vector<int32_t>>{}, {}, comm);
  // The checkpoint to continue from is opened and checked first: the output folder, opened
  // next, may be the very folder it lies in (its .partial is cleared then).
  check_checkpoint_use(config, !restart_folder.empty());
  if (!restart_folder.empty()) restart = std::make_unique<Restart>(restart_folder, config, comm);
  // First, before any work: a second run on the same output folder stops here, at once.
  auto output_folder = open_output_folder(config.output.folder, comm);
  load_mesh();
  make_solver();
  recorder = std::make_unique<ResultRecorder>(*problem, config, std::move(output_folder), comm);
  t_setup = MPI_Wtime() - t_start;

  // Owned: an input error found after this point (a cavity volume that cannot exist, a control
  // target out of reach) leaves the caller's process going.
  u = VecHandle(problem->create_vector());
  {
    VecHandle f;
    HS_PETSC(VecDuplicate(u, f.out()));
    problem->external_load(u, 1.0, f);
    PetscReal norm = 0;
    HS_PETSC(VecNorm(f, NORM_2, &norm));
    if (newton) newton->scale_absolute_tolerance(norm);
    if (bordered) bordered->set_load_norm(norm);
  }
  checkpoints = std::make_unique<Checkpointer>(config, *problem, stats, recorder->staging(), comm);
  if (restart) {
    restart->restore(stats);
    recorder->set_newton_before(stats.newton_iterations);
  }
}

void RunSetup::load_mesh() {
  dist = load_distributed_mesh(config.mesh, comm, &mesh_times, config.solver);
  check_groups(config, dist.groups);
  check_rigid_motions_held(config, dist.node_groups, dist.x, comm);
  exact = make_exact_solution(config);
  if (exact) check_reference_finite(config, *exact, dist.x, comm);
  // Two entries that prescribe one node's component differently: refused before any solve.
  // Every rank knows all the groups of its nodes, ghosts included, so each conflict is seen.
  check_boundary_conflicts(config, dist.node_groups, dist.x, dist.num_owned(),
                           exact_dirichlet_of(exact.get()), comm);
  problem = make_problem(config, dist, comm, exact.get());
  if (restart) restart->check_mesh(*problem);
}

ExactDirichlet exact_dirichlet_of(const ExactSolution* exact) {
  if (!exact) return {};
  return [exact](const std::array<double, 3>& X, double s) { return exact->displacement(X, s); };
}

std::unique_ptr<Problem> make_problem(const Config& config, const Distribution& dist, MPI_Comm comm,
                                      const ExactSolution* exact) {
  ForceDensity body_force;
  if (exact && exact->has_body_force())
    body_force = [exact](const std::array<double, 3>& X) { return exact->body_force(X); };
  return std::make_unique<Problem>(config, dist, comm, exact_dirichlet_of(exact), body_force);
}

// A scene with constraints (cavities, cables, states, control) solves with the bordered
// Newton (displacements and multipliers); any other with the plain SNES.
void RunSetup::make_solver() {
  if (has_constraints(kind)) constraints = std::make_unique<ConstraintSet>(config, *problem);
  // Symmetric unless the deck puts a follower pressure on an open surface or a constraint's
  // forces are no gradient (a cable with friction). Definite (CG) only for linear laws without
  // any pressure stiffness (a cavity's can make the tangent indefinite near a limit point).
  bool linear_laws = true;
  for (const auto& m : config.materials) linear_laws &= m.law->tangent_always_definite();
  TangentKind tangent;
  tangent.symmetric =
      !problem->has_open_surface_pressure() && (!constraints || constraints->symmetric());
  tangent.definite = linear_laws && !problem->has_follower_loads();
  tangent.nodal_pressure = problem->has_nodal_pressure();
  if (constraints)
    bordered = std::make_unique<BorderedNewton>(*problem, *constraints, config.solver, tangent);
  else
    newton = std::make_unique<NewtonSolver>(*problem, config.solver, tangent);
}

nlohmann::json RunSetup::summary() {
  int size = 1;
  MPI_Comm_size(comm, &size);
  nlohmann::json summary;
  summary["deck"] = config.deck_path;
  summary["ranks"] = size;
  summary["dofs"] = problem->num_global_dofs();
  summary["nodes"] = dist.num_global();
  summary["elements"] = dist.num_global_tets;
  summary["order"] = dist.order;
  for (const auto& m : config.materials)
    summary["materials"].push_back({{"group", m.group},
                                    {"model", m.law->name()},
                                    {"formulation", name_of(kElementFormulationNames, m.element)},
                                    {"formulation_reason", m.formulation_reason}});
  if (problem->has_volume_multipliers()) {
    const auto& k = problem->volume_keeping();
    summary["incompressibility"] = {{"volume_tolerance", kVolumeTolerance},
                                    {"last_volume_change", k.last_change},
                                    {"solves", k.solves},
                                    {"multiplier_raises", k.raises},
                                    {"most_raises_in_a_solve", k.most_raises}};
  }
  summary["steps"] = stats.steps;
  summary["cutbacks"] = stats.cutbacks;
  summary["newton_iterations"] = stats.newton_iterations;
  summary["linear_iterations"] = stats.linear_iterations;
  summary["outputs"] = recorder->written();
  add_timings(summary, *problem, dist, mesh_times, *recorder, comm);
  summary["time_s"]["setup"] = t_setup;
  auto slowest = [this](double seconds) {
    MPI_Allreduce(MPI_IN_PLACE, &seconds, 1, MPI_DOUBLE, MPI_MAX, comm);
    return seconds;
  };
  summary["time_s"]["solve"] = slowest(solver().solve_seconds());
  if (constraints) {
    summary["parts"] = constraints->parts();
    summary["time_s"]["fluid_weight"] = slowest(constraints->fluid_weight_seconds());
    summary["time_s"]["constraint"] = slowest(bordered->constraint_seconds());
    summary["time_s"]["constraint_build"] = slowest(constraints->constraint_build_seconds());
  } else {
    summary["parts"] = {{"cavities", 0},
                        {"cables", 0},
                        {"fluid_weight", {{"cavities", 0}, {"device", "none"}, {"method", "none"}}},
                        {"cuda_context", false}};
  }
  summary["output"]["xdmf"] = recorder->xdmf_path();
  if (restart) summary["restarted_from"] = restart->summary();
  summary["time_s"]["total"] = MPI_Wtime() - t_start;
  return summary;
}

}  // namespace hs
