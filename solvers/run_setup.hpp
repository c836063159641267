// The parts of one run (solvers/simulation.cpp), made in the order the checks need: the
// deck's checks that need no mesh, the checkpoint to continue from, the output folder (a
// second run on it stops there, before any work), the mesh and its checks, the problem, its
// constraints and nonlinear solver, the output and the checkpoints. Collective; an error
// before any step reaches the caller as InputError.
#pragma once

#include <mpi.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "deck/config.hpp"
#include "mesh/distribution.hpp"
#include "solvers/bordered_newton.hpp"
#include "solvers/checkpoint.hpp"
#include "solvers/constraints/constraint_set.hpp"
#include "solvers/distributed_mesh.hpp"
#include "solvers/newton_solver.hpp"
#include "solvers/output/result_recorder.hpp"
#include "solvers/problem.hpp"
#include "solvers/stepping.hpp"
#include "solvers/stepping/stepper.hpp"
#include "solvers/stepping/stepping_kind.hpp"
#include "verification/exact_solution.hpp"

namespace hs {

// The deck's problem on `dist`: its exact section's (if any: `exact`, which must outlive it)
// Dirichlet values and body force with it.
std::unique_ptr<Problem> make_problem(const Config& config, const Distribution& dist, MPI_Comm comm,
                                      const ExactSolution* exact);
ExactDirichlet exact_dirichlet_of(const ExactSolution* exact);

class RunSetup {
 public:
  RunSetup(const Config& config, MPI_Comm comm, const std::string& restart_folder);
  RunSetup(const RunSetup&) = delete;
  RunSetup& operator=(const RunSetup&) = delete;

  NonlinearSolver& solver() { return newton ? static_cast<NonlinearSolver&>(*newton) : *bordered; }
  StepperParts stepper_parts() {
    return {config, *problem, solver(), stats, constraints.get(), bordered.get(), recorder.get()};
  }
  // summary.json's keys that any run has, ended or failed: sizes, counts, timings.
  nlohmann::json summary();

  const Config& config;
  const MPI_Comm comm;
  const double t_start;
  const SteppingKind kind;
  double t_setup = 0;
  std::unique_ptr<Restart> restart;  // --restart
  MeshLoadTimes mesh_times;
  Distribution dist;
  // The deck's exact solution, if any: the values of Dirichlet conditions marked exact, and
  // the reference of the errors and verification quantities.
  std::unique_ptr<const ExactSolution> exact;
  std::unique_ptr<Problem> problem;
  std::unique_ptr<ConstraintSet> constraints;  // with constraints only
  std::unique_ptr<NewtonSolver> newton;        // without constraints
  std::unique_ptr<BorderedNewton> bordered;    // with constraints
  std::unique_ptr<ResultRecorder> recorder;
  VecHandle u;
  SteppingStats stats;
  std::unique_ptr<Checkpointer> checkpoints;

 private:
  void load_mesh();
  void make_solver();
};

}  // namespace hs
