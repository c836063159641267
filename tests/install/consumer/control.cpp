// Drives hydrosoft's inverse controller from another program, through the installed libraries
// (tests/install/): the hydraulic finger of the installed input/finger_hydraulic.yaml, meshed
// coarse, hangs under gravity with its cavity open (the rest state; -9.5 mm on this mesh), and
// the controller steers its tip to a height of -8 mm. The answer is checked against a
// forward solve at the pressure the controller found: the tip must be where the controller
// says it is, and that within 0.05 mm of the target. Run on any number of ranks.
//
// The classes used are the controller's public interface (solvers/inverse_controller.hpp):
//   Problem (the body), ConstraintSet (its cavities), BorderedNewton (equilibrium with them),
//   Effectors (the points steered) and InverseController (one control step at a time).
#include <petscsys.h>

#include <cmath>
#include <cstdio>

#include "deck/deck.hpp"
#include "solvers/bordered_newton.hpp"
#include "solvers/constraints/constraint_set.hpp"
#include "solvers/distributed_mesh.hpp"
#include "solvers/effectors.hpp"
#include "solvers/inverse_controller.hpp"
#include "solvers/newton_solver.hpp"
#include "solvers/problem.hpp"

namespace {

// Equilibrium at cavity pressure p (Pa, gauge) with gravity at load factor s, from u.
bool solve_at(hs::Problem& problem, hs::ConstraintSet& cavities, hs::BorderedNewton& newton, Vec u,
              double p, double s) {
  hs::Constraint& cavity = cavities[0];
  cavity.prescribe(hs::Constraint::Control::multiplier, p);
  problem.apply_dirichlet(u, s);
  return newton.solve(u, s).converged;
}

bool steer_the_finger(int rank) {
  const hs::Config config =
      hs::parse_deck(HYDROSOFT_CONTROL_DECK,
                     {"mesh.parameters.h=0.006", "control.targets=[{tip: [0.09, 0, -0.008]}]"});
  const hs::Distribution dist = hs::load_distributed_mesh(config.mesh, PETSC_COMM_WORLD);
  hs::Problem problem(config, dist, PETSC_COMM_WORLD);
  hs::ConstraintSet cavities(config, problem);
  hs::BorderedNewton newton(problem, cavities, config.solver,
                            hs::TangentKind{cavities.symmetric(), false});
  hs::Effectors effectors(config, problem);

  // The rest state: gravity ramped in over 4 increments, the cavity at gauge pressure 0.
  Vec rest = problem.create_vector(), f = problem.create_vector();
  problem.external_load(rest, 1.0, f);
  PetscReal load = 0;
  VecNorm(f, NORM_2, &load);
  VecDestroy(&f);
  newton.set_load_norm(load);
  bool ok = true;
  for (double s : {0.25, 0.5, 0.75, 1.0})
    ok = ok && solve_at(problem, cavities, newton, rest, 0, s);

  // The controller: steps_per_target steps towards the target, then the equilibrium there.
  const std::vector<hs::ControlTarget> targets = config.control->targets.at(0);
  Vec u = problem.create_vector();
  VecCopy(rest, u);
  hs::ControlStepReport answer;
  {
    hs::InverseController controller(config, problem, cavities, newton, effectors);
    controller.set_rest(u);
    for (int k = 0; k < config.control->steps_per_target; ++k) answer = controller.step(u, targets);
    controller.settle(u, answer);
  }
  const double pressure = answer.actuation.at(0), target_z = targets.at(0).position[2];

  // The same finger pushed forward to that pressure, in 4 increments from rest. Newton's
  // tangent linearises a nearly incompressible body's pressures from its previous point
  // (docs/formulation.md), the controller's answer here: from rest, far from it, the solve
  // takes the exact tangent (without, it converged to a ballooned equilibrium with the tip at
  // -78 mm).
  Vec v = problem.create_vector();
  VecCopy(rest, v);
  problem.exact_next_tangent();
  for (int k = 1; k <= 4; ++k)
    ok = ok && solve_at(problem, cavities, newton, v, pressure * k / 4, 1);
  const std::vector<double> forward = effectors.positions(v);
  VecDestroy(&v);
  VecDestroy(&u);
  VecDestroy(&rest);

  const double controller_z = answer.reached.at(2), forward_z = forward.at(2);
  if (rank == 0)
    std::printf(
        "controller: target z %.3f mm, pressure %.1f Pa, tip z %.4f mm (controller), "
        "%.4f mm (forward solve at that pressure)\n",
        1e3 * target_z, pressure, 1e3 * controller_z, 1e3 * forward_z);
  // Newton's tolerance on both sides: 1e-7 m; the controller's error after its steps: 0.05 mm.
  return ok && std::fabs(controller_z - forward_z) < 1e-7 &&
         std::fabs(controller_z - target_z) < 5e-5 && pressure > 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (PetscInitialize(&argc, &argv, nullptr, nullptr) != 0) return 1;
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  bool ok = false;
  try {
    ok = steer_the_finger(rank);
  } catch (const std::exception& e) {
    std::printf("error: %s\n", e.what());
  }
  PetscFinalize();
  if (rank == 0) std::printf("%s\n", ok ? "control: all checks passed" : "control: a check failed");
  return ok ? 0 : 1;
}
