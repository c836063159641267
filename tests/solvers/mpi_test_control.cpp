// The inverse controller against forward simulations, on 1 and 2 ranks: a target that a
// forward run reaches with a known pressure is reached to 0.1 mm with that pressure, by the
// pneumatic and by the hydraulic cylinder (the liquid's weight acting through the unified
// constraint); a target beyond the pressure bound ends on the forward run at the bound, with
// the actuator marked saturated.
#include <gtest/gtest.h>
#include <petscsnes.h>

#include <cmath>
#include <filesystem>

#include "deck/deck.hpp"
#include "mesh/distribution.hpp"
#include "mesh/gmsh_io.hpp"
#include "solvers/bordered_newton.hpp"
#include "solvers/cavity_system.hpp"
#include "solvers/effectors.hpp"
#include "solvers/inverse_controller.hpp"
#include "solvers/newton_solver.hpp"
#include "solvers/problem.hpp"

namespace {

const std::string kSource = HYDROSOFT_SOURCE_DIR;

// The cylinder at rest under gravity, ready for forward runs and for the controller.
struct Scene {
  hs::Config config;
  hs::Mesh mesh;
  hs::Distribution dist;
  std::unique_ptr<hs::Problem> problem;
  std::unique_ptr<hs::CavitySystem> cavities;
  std::unique_ptr<hs::BorderedNewton> newton;
  std::unique_ptr<hs::Effectors> effectors;
  Vec rest = nullptr;

  Scene(const std::string& deck, double max_pressure) {
    config = hs::parse_deck(kSource + "/input/" + deck, {});
    hs::ControlConfig control;
    hs::EffectorConfig tip;
    tip.name = "tip";
    tip.position = {0.0, 0.0, -0.15};  // centre of the free end face
    control.effectors = {tip};
    hs::ActuatorConfig actuator;
    actuator.cavity = "cavity";
    actuator.max_pressure = max_pressure;
    control.actuators = {actuator};
    control.newton_finish = true;
    config.control = control;
    mesh = hs::load_mesh_replicated(config.mesh, PETSC_COMM_WORLD);
    int rank, size;
    MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
    MPI_Comm_size(PETSC_COMM_WORLD, &size);
    dist = hs::distribute(mesh, hs::partition_tets(mesh, size), rank, size);
    problem = std::make_unique<hs::Problem>(config, mesh, dist, PETSC_COMM_WORLD);
    cavities = std::make_unique<hs::CavitySystem>(config, *problem, mesh, dist);
    hs::set_solver_options(config.solver, false);
    newton = std::make_unique<hs::BorderedNewton>(*problem, *cavities);
    effectors = std::make_unique<hs::Effectors>(config, *problem);
    rest = problem->create_vector();
    Vec f = problem->create_vector();
    problem->external_load(rest, 1.0, f);
    PetscReal norm = 0;
    VecNorm(f, NORM_2, &norm);
    VecDestroy(&f);
    newton->set_load_norm(norm);
    for (double s : {0.25, 0.5, 0.75, 1.0}) solve_at_pressure(rest, 0.0, s);
  }
  ~Scene() { VecDestroy(&rest); }

  void solve_at_pressure(Vec u, double p, double s = 1.0) {
    hs::Cavity& c = (*cavities)[0];
    c.control = hs::CavityControl::pressure;
    c.target = c.lambda = p;
    problem->apply_dirichlet(u, s);
    if (cavities->linearized()) cavities->freeze_weights(u, s);
    const auto r = newton->solve(u, s);
    ASSERT_TRUE(r.converged) << r.reason;
  }

  // The tip's position after a forward run to pressure p from rest.
  std::array<double, 3> forward(double p) {
    Vec u = problem->create_vector();
    VecCopy(rest, u);
    for (int k = 1; k <= 4; ++k) solve_at_pressure(u, p * k / 4);
    const auto x = effectors->positions(u);
    VecDestroy(&u);
    (*cavities)[0].lambda = 0;
    return {x[0], x[1], x[2]};
  }
};

void expect_reaches(const std::string& deck, const std::string& free_solve = "newton",
                    int refactor_every = 1) {
  Scene s(deck, 1e300);
  s.config.control->free_solve = free_solve;
  s.config.control->refactor_every = refactor_every;
  const double p = 3000;
  const auto target = s.forward(p);
  Vec u = s.problem->create_vector();
  VecCopy(s.rest, u);
  hs::InverseController controller(s.config, *s.problem, *s.cavities, *s.newton, *s.effectors);
  controller.set_rest(u);
  hs::ControlStepReport r;
  for (int k = 0; k < 8; ++k) r = controller.step(u, {{"tip", target}});
  EXPECT_LT(r.error, 1e-4) << deck;
  // The equilibrium at the final actuation (the one_step mode reports a prediction).
  const auto x = controller.equilibrium_positions(u);
  double error2 = 0;
  for (int d = 0; d < 3; ++d) error2 += std::pow(x[d] - target[d], 2);
  EXPECT_LT(std::sqrt(error2), 1e-4) << deck << " " << free_solve << " " << refactor_every;
  EXPECT_NEAR(r.actuation[0], p, 0.01 * p) << deck;
  EXPECT_FALSE(r.saturated[0]);
  EXPECT_TRUE(r.qp_solved);
  EXPECT_LT(r.kkt_residual, 1e-8);
  VecDestroy(&u);
}

TEST(Control, PneumaticCylinderReachesAForwardRunsTarget) { expect_reaches("cylinder_air.yaml"); }

TEST(Control, HydraulicCylinderReachesAForwardRunsTarget) { expect_reaches("cylinder_water.yaml"); }

TEST(Control, OneLinearisationPerStepReachesTheTargetToo) {
  // The paper's real-time step (one assembly and factorization for the free motion and the
  // compliance), and the same with the factorization kept for three steps.
  expect_reaches("cylinder_water.yaml", "one_step", 1);
  expect_reaches("cylinder_water.yaml", "one_step", 3);
}

TEST(Control, UnreachableTargetSaturatesAtTheBound) {
  const double bound = 2000;
  Scene s("cylinder_air.yaml", bound);
  const auto at_bound = s.forward(bound);
  const auto beyond = s.forward(2.5 * bound);
  Vec u = s.problem->create_vector();
  VecCopy(s.rest, u);
  hs::InverseController controller(s.config, *s.problem, *s.cavities, *s.newton, *s.effectors);
  controller.set_rest(u);
  hs::ControlStepReport r;
  for (int k = 0; k < 8; ++k) r = controller.step(u, {{"tip", beyond}});
  EXPECT_NEAR(r.actuation[0], bound, 1e-6 * bound);
  EXPECT_TRUE(r.saturated[0]);
  for (int d = 0; d < 3; ++d) EXPECT_NEAR(r.reached[d], at_bound[d], 1e-4) << d;
  EXPECT_GT(r.error, 1e-3);  // the target really is out of reach
  VecDestroy(&u);
}

}  // namespace
