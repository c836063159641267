// A scene for controller tests: a deck at rest under gravity (4 load steps), one effector
// and one actuator (constraint 0 of the cavity system: the deck's first cavity, or its
// cable when it has no cavity), with forward runs at a given actuation to make targets.
#pragma once

#include <gtest/gtest.h>
#include <petscsnes.h>

#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "../mpi_test_decks.hpp"
#include "deck/deck.hpp"
#include "distribute_whole.hpp"
#include "mesh/distribution.hpp"
#include "mesh/gmsh_io.hpp"
#include "solvers/bordered_newton.hpp"
#include "solvers/constraints/constraint_set.hpp"
#include "solvers/effectors.hpp"
#include "solvers/inverse_controller.hpp"
#include "solvers/newton_solver.hpp"
#include "solvers/problem.hpp"

namespace hs_test {

// A deck of input/ read, meshed, distributed over PETSC_COMM_WORLD, and its Problem.
struct DeckProblem {
  hs::Config config;
  hs::Mesh mesh;
  hs::Distribution dist;
  std::unique_ptr<hs::Problem> problem;

  DeckProblem(const std::string& deck, const std::vector<std::string>& overrides,
              const std::function<void(hs::Config&)>& adjust = nullptr) {
    config = hs::parse_deck(std::string(HYDROSOFT_SOURCE_DIR) + "/input/" + deck, overrides);
    if (adjust) adjust(config);
    mesh = hs::load_mesh(config.mesh);  // gmsh is deterministic: the same on every rank
    dist = distribute_whole(mesh);
    problem = std::make_unique<hs::Problem>(config, dist, PETSC_COMM_WORLD);
  }
};

struct ControlScene : DeckProblem {
  std::unique_ptr<hs::ConstraintSet> cavities;
  std::unique_ptr<hs::BorderedNewton> newton;
  std::unique_ptr<hs::Effectors> effectors;
  hs::VecHandle rest;

  // deck: a file of input/; effector: its reference position; actuator: its bounds.
  ControlScene(const std::string& deck, const std::array<double, 3>& effector,
               hs::ActuatorConfig actuator, const std::vector<std::string>& overrides = {})
      : DeckProblem(deck, overrides, [&](hs::Config& config) {
          hs::ControlConfig control;
          hs::EffectorConfig tip;
          tip.name = "tip";
          tip.position = effector;
          control.effectors = {tip};
          control.actuators = {actuator};
          control.newton_finish = true;
          config.control = control;
        }) {
    cavities = std::make_unique<hs::ConstraintSet>(config, *problem);
    newton = std::make_unique<hs::BorderedNewton>(*problem, *cavities, config.solver,
                                                  hs::TangentKind{false, true});
    effectors = std::make_unique<hs::Effectors>(config, *problem);
    rest = hs::VecHandle(problem->create_vector());
    const hs::VecHandle f(problem->create_vector());
    problem->external_load(rest, 1.0, f);
    PetscReal norm = 0;
    VecNorm(f, NORM_2, &norm);
    newton->set_load_norm(norm);
    for (double s : {0.25, 0.5, 0.75, 1.0}) solve_at(rest, 0.0, s);
  }

  // Equilibrium at actuation p of constraint 0 (pressure or tension), load factor s.
  void solve_at(Vec u, double p, double s = 1.0) {
    hs::Constraint& c = (*cavities)[0];
    c.prescribe(hs::Constraint::Control::multiplier, p);
    problem->apply_dirichlet(u, s);
    if (cavities->linearized()) cavities->freeze_weights(u, s);
    const auto r = newton->solve(u, s);
    ASSERT_TRUE(r.converged) << r.reason;
  }

  // `steps` control steps from rest towards `target`: the last step's report, and the
  // equilibrium at its actuation in `equilibrium` when asked.
  hs::ControlStepReport drive(const std::array<double, 3>& target, int steps,
                              std::vector<double>* equilibrium = nullptr) {
    const hs::VecHandle u(problem->create_vector());
    VecCopy(rest, u);
    hs::InverseController controller(config, *problem, *cavities, *newton, *effectors);
    controller.set_rest(u);
    hs::ControlStepReport r;
    for (int k = 0; k < steps; ++k) r = controller.step(u, {{"tip", target}});
    if (equilibrium) *equilibrium = controller.equilibrium_positions(u);
    return r;
  }

  // The effector's position after a forward run to actuation p from rest (4 increments).
  std::array<double, 3> forward(double p) {
    const hs::VecHandle u(problem->create_vector());
    VecCopy(rest, u);
    for (int k = 1; k <= 4; ++k) solve_at(u, p * k / 4);
    const auto x = effectors->positions(u);
    (*cavities)[0].set_multiplier(0);
    return {x[0], x[1], x[2]};
  }
};

}  // namespace hs_test
