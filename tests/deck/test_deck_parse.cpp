// parse_deck on valid decks: every key read, defaults, E/nu <-> mu/lambda, the round trip
// parse -> format_config -> parse, and command-line overrides.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/error.hpp"
#include "deck/cavity_sections.hpp"
#include "deck/deck.hpp"
#include "materials/gent.hpp"
#include "materials/mooney_rivlin.hpp"
#include "temp_folder.hpp"
#include "verification/registry.hpp"

namespace hs {
namespace {

using testing::TempFolder;

// Every key of the format, with values that differ from the defaults.
const char* kFullDeck = R"(# a deck that uses every key
mesh:
  file: ../meshes/body.geo
  order: 2
  parameters: {h: 0.05, a: 1.5}
  refine: 1
  trust_geo: true
  max_elements: 5000000
materials:
  - {group: body, model: neo_hookean, E: 2.98e5, nu: 0.49, density: 1100}
  - {group: insert, model: linear_elastic, mu: 1.0e5, lambda: 2.0e5}
  - {group: skin, model: mooney_rivlin, E: 3.0e4, nu: 0.45, c1: 4000, c2: 1000, density: 1000}
  - {group: core, model: gent, mu: 2.0e4, lambda: 1.0e6, Jm: 25}
boundary:
  - {group: clamp}
  - {group: slide, components: [z, x], value: [0.5, 0, -0.25], scaled: false}
  - {group: inner, exact: true}
loads:
  gravity: [0, -9.81, 0.5]
  pressure:
    - {group: inner, value: 2.5e3}
    - {group: outer, value: -10}
time:
  type: quasi_static
  schedule: [0.25, 0.5, 1.0, 0.75]
  max_cutbacks: 3
solver:
  preset: gamg
  petsc_options: {snes_rtol: 1e-10, ksp_type: cg, snes_monitor: , pc_gamg_threshold: 0.02}
output: {folder: results/run1, every: 2}
exact:
  type: lame_sphere
  parameters: {a: 1, b: 2, p: 2.5e3}
)";

// Every key of the cavities, states and tip sections; each kind of cavity once.
const char* kCavityDeck = R"(mesh: {file: body.msh}
materials:
  - {group: body, model: neo_hookean, E: 1.0e5, nu: 0.45, density: 1070}
boundary:
  - {group: top}
loads: {gravity: [0, -9.81, 0]}
cavities:
  - group: cavity
    kind: hydraulic
    added_volume: 1.5e-5
    density: 13600
    fluid_weight: {method: column, grid: 64, device: cuda, coupling: linearized}
  - {group: bladder, kind: pneumatic, pressure: 2.0e3}
  - {group: open}
  - {group: chamber, kind: sealed_gas, initial_pressure: -5.0e3, atmospheric_pressure: 1.0e5}
  - {group: core, kind: sealed_volume}
  - {group: water, kind: hydraulic, fluid_weight: {device: cpu}}
  - {group: bubble, kind: sealed_gas}
time: {type: quasi_static, max_cutbacks: 4}
states:
  - name: rest
    steps: 4
  - name: inflated
    steps: 10
    cavities:
      cavity: {added_volume: 3.0e-5}
      bladder: {pressure: 5.0e3}
    move: {top: [0, 1.0e-3, 0]}
  - {name: hold}
tip: {group: tip}
contact:
  surfaces: [skin, tip]
  self: true
  friction: 0.5
  friction_between: [{surfaces: [skin, tip], friction: 0.2}, {surfaces: [tip, tip], friction: 0}]
)";

// Every key of the control section: an effector at a mesh node and one at a material point,
// a hydraulic and a pneumatic actuator (one with every bound, one with equal pressure bounds),
// target sets naming one or both effectors; after states, whose end is the rest state.
const char* kControlDeck = R"(mesh: {file: body.msh}
materials:
  - {group: body, model: neo_hookean, E: 2.0e5, nu: 0.45, density: 1070}
boundary:
  - {group: base}
loads: {gravity: [0, 0, -9.81]}
cavities:
  - {group: upper, kind: hydraulic, density: 1000}
  - {group: lower, kind: pneumatic, pressure: 500}
  - {group: bubble, kind: sealed_gas}
time: {type: quasi_static}
states:
  - {name: rest, steps: 3}
control:
  effectors:
    - name: tip
      point: effector
      directions: [z, x]
      weight: 2.5
    - {name: side, position: [0.045, 0.009, -0.25e-3]}
  actuators:
    - cavity: upper
      min_pressure: -1.5e3
      max_pressure: 2.0e4
      min_volume_growth: -1.0e-6
      max_volume_growth: 2.0e-5
      max_pressure_change: 2000
    - {cavity: lower, min_pressure: 0, max_pressure: 0}
  targets:
    - {tip: [0.09, 0.0, -0.01]}
    - {side: [0.05, 0.01, 0.0], tip: [0.08, 0.0, 0.02]}
    - tip: [0.085, 0.001, 0.015]
      side: [0.044, 0.009, 0.003]
  steps_per_target: 25
  regularization: 0
  newton_finish: true
  free_solve: one_step
)";

// The smallest control section: defaults for everything else.
const char* kMinimalControlDeck = R"(mesh: {file: body.msh}
materials: [{group: body, model: neo_hookean, E: 2.0e5, nu: 0.45}]
cavities: [{group: cavity}]
control:
  effectors: [{name: tip, point: effector}]
  actuators: [{cavity: cavity, max_pressure: 2.0e4}]
)";

const char* kDynamicDeck = R"(mesh: {file: body.msh}
materials:
  - {group: body, model: corotational, E: 1.0e6, nu: 0.3, density: 1000}
time: {type: dynamic, dt: 0.01, end_time: 0.5, newmark: {beta: 0.3025, gamma: 0.6}}
)";

const ElasticConstants& elastic(const MaterialConfig& m) { return m.law->elastic_constants(); }
const MooneyRivlinLaw& mooney_rivlin(const MaterialConfig& m) {
  return dynamic_cast<const MooneyRivlinLaw&>(*m.law);
}
const GentLaw& gent(const MaterialConfig& m) { return dynamic_cast<const GentLaw&>(*m.law); }
// A law's response at a moderate strain (inside every law's domain): the same parameters give
// the same bits, whatever the law, so a key of its own that did not print back shows here.
StressResult response(const MaterialConfig& m) {
  Mat3 F;
  F << 1.1, 0.05, 0.0, -0.03, 0.95, 0.02, 0.01, 0.0, 1.05;
  return stress(*m.law, F);
}

void expect_same(const Config& a, const Config& b) {
  ASSERT_EQ(a.cables.size(), b.cables.size());
  for (size_t i = 0; i < a.cables.size(); ++i) {
    EXPECT_EQ(a.cables[i].name, b.cables[i].name);
    EXPECT_EQ(a.cables[i].points, b.cables[i].points);
    EXPECT_EQ(a.cables[i].pull_point, b.cables[i].pull_point);
    EXPECT_EQ(a.cables[i].force, b.cables[i].force);
  }
  EXPECT_EQ(a.mesh.file, b.mesh.file);
  EXPECT_EQ(a.mesh.order, b.mesh.order);
  EXPECT_EQ(a.mesh.parameters, b.mesh.parameters);
  EXPECT_EQ(a.mesh.refine, b.mesh.refine);
  EXPECT_EQ(a.mesh.trust_geo, b.mesh.trust_geo);
  EXPECT_EQ(a.mesh.max_elements, b.mesh.max_elements);
  ASSERT_EQ(a.materials.size(), b.materials.size());
  for (size_t i = 0; i < a.materials.size(); ++i) {
    const auto &m = a.materials[i], &n = b.materials[i];
    EXPECT_EQ(m.group, n.group);
    EXPECT_EQ(m.law->name(), n.law->name());
    EXPECT_EQ(elastic(m).E, elastic(n).E);  // bitwise: the printed numbers are exact
    EXPECT_EQ(elastic(m).nu, elastic(n).nu);
    EXPECT_EQ(elastic(m).mu, elastic(n).mu);
    EXPECT_EQ(elastic(m).lambda, elastic(n).lambda);
    EXPECT_EQ(response(m).P, response(n).P);  // the keys of its own: c1, c2, Jm, C2, C3
    EXPECT_EQ(response(m).psi, response(n).psi);
    EXPECT_EQ(m.density, n.density);
  }
  ASSERT_EQ(a.dirichlet.size(), b.dirichlet.size());
  for (size_t i = 0; i < a.dirichlet.size(); ++i) {
    EXPECT_EQ(a.dirichlet[i].group, b.dirichlet[i].group);
    EXPECT_EQ(a.dirichlet[i].components, b.dirichlet[i].components);
    EXPECT_EQ(a.dirichlet[i].value, b.dirichlet[i].value);
    EXPECT_EQ(a.dirichlet[i].scaled, b.dirichlet[i].scaled);
    EXPECT_EQ(a.dirichlet[i].exact, b.dirichlet[i].exact);
  }
  EXPECT_EQ(a.gravity, b.gravity);
  ASSERT_EQ(a.pressures.size(), b.pressures.size());
  for (size_t i = 0; i < a.pressures.size(); ++i) {
    EXPECT_EQ(a.pressures[i].group, b.pressures[i].group);
    EXPECT_EQ(a.pressures[i].value, b.pressures[i].value);
  }
  EXPECT_EQ(a.time.type, b.time.type);
  EXPECT_EQ(a.time.steps, b.time.steps);
  EXPECT_EQ(a.time.schedule, b.time.schedule);
  EXPECT_EQ(a.time.dt, b.time.dt);
  EXPECT_EQ(a.time.end_time, b.time.end_time);
  EXPECT_EQ(a.time.integrator, b.time.integrator);
  EXPECT_EQ(a.time.newmark_beta, b.time.newmark_beta);
  EXPECT_EQ(a.time.newmark_gamma, b.time.newmark_gamma);
  EXPECT_EQ(a.time.max_cutbacks, b.time.max_cutbacks);
  EXPECT_EQ(a.solver.preset, b.solver.preset);
  EXPECT_EQ(a.solver.petsc_options, b.solver.petsc_options);
  EXPECT_EQ(a.output.folder, b.output.folder);
  EXPECT_EQ(a.output.every, b.output.every);
  EXPECT_EQ(a.exact.type, b.exact.type);  // the same registry entry
  EXPECT_EQ(a.exact.parameters, b.exact.parameters);
  ASSERT_EQ(a.cavities.size(), b.cavities.size());
  for (size_t i = 0; i < a.cavities.size(); ++i) {
    const auto &p = a.cavities[i], &q = b.cavities[i];
    EXPECT_EQ(p.group, q.group);
    EXPECT_EQ(p.kind, q.kind);
    EXPECT_EQ(p.pressure, q.pressure);
    EXPECT_EQ(p.added_volume, q.added_volume);
    EXPECT_EQ(p.density, q.density);
    EXPECT_EQ(p.fluid_weight.method, q.fluid_weight.method);
    EXPECT_EQ(p.fluid_weight.grid, q.fluid_weight.grid);
    EXPECT_EQ(p.fluid_weight.device, q.fluid_weight.device);
    EXPECT_EQ(p.fluid_weight.coupling, q.fluid_weight.coupling);
    EXPECT_EQ(p.initial_pressure, q.initial_pressure);
    EXPECT_EQ(p.atmospheric_pressure, q.atmospheric_pressure);
  }
  ASSERT_EQ(a.states.size(), b.states.size());
  for (size_t i = 0; i < a.states.size(); ++i) {
    EXPECT_EQ(a.states[i].name, b.states[i].name);
    EXPECT_EQ(a.states[i].steps, b.states[i].steps);
    ASSERT_EQ(a.states[i].cavities.size(), b.states[i].cavities.size());
    for (const auto& [name, target] : a.states[i].cavities) {
      ASSERT_TRUE(b.states[i].cavities.count(name)) << name;
      EXPECT_EQ(target.pressure, b.states[i].cavities.at(name).pressure);
      EXPECT_EQ(target.added_volume, b.states[i].cavities.at(name).added_volume);
    }
  }
  ASSERT_EQ(a.tip.has_value(), b.tip.has_value());
  if (a.tip) EXPECT_EQ(a.tip->group, b.tip->group);
  ASSERT_EQ(a.control.has_value(), b.control.has_value());
  if (!a.control) return;
  const ControlConfig &p = *a.control, &q = *b.control;
  ASSERT_EQ(p.effectors.size(), q.effectors.size());
  for (size_t i = 0; i < p.effectors.size(); ++i) {
    EXPECT_EQ(p.effectors[i].name, q.effectors[i].name);
    EXPECT_EQ(p.effectors[i].point, q.effectors[i].point);
    EXPECT_EQ(p.effectors[i].position, q.effectors[i].position);
    EXPECT_EQ(p.effectors[i].directions, q.effectors[i].directions);
    EXPECT_EQ(p.effectors[i].weight, q.effectors[i].weight);
  }
  ASSERT_EQ(p.actuators.size(), q.actuators.size());
  for (size_t i = 0; i < p.actuators.size(); ++i) {
    EXPECT_EQ(p.actuators[i].constraint, q.actuators[i].constraint);
    EXPECT_EQ(p.actuators[i].min_multiplier, q.actuators[i].min_multiplier);
    EXPECT_EQ(p.actuators[i].max_multiplier, q.actuators[i].max_multiplier);
    EXPECT_EQ(p.actuators[i].min_measure_change, q.actuators[i].min_measure_change);
    EXPECT_EQ(p.actuators[i].max_measure_change, q.actuators[i].max_measure_change);
    EXPECT_EQ(p.actuators[i].max_multiplier_step, q.actuators[i].max_multiplier_step);
  }
  ASSERT_EQ(p.targets.size(), q.targets.size());
  for (size_t i = 0; i < p.targets.size(); ++i) {
    ASSERT_EQ(p.targets[i].size(), q.targets[i].size());
    for (size_t j = 0; j < p.targets[i].size(); ++j) {
      EXPECT_EQ(p.targets[i][j].effector, q.targets[i][j].effector);
      EXPECT_EQ(p.targets[i][j].position, q.targets[i][j].position);
    }
  }
  EXPECT_EQ(p.moves, q.moves);
  EXPECT_EQ(p.steps_per_target, q.steps_per_target);
  EXPECT_EQ(p.regularization, q.regularization);
  EXPECT_EQ(p.newton_finish, q.newton_finish);
  EXPECT_EQ(p.free_solve, q.free_solve);
  EXPECT_EQ(p.targets_from_stdin, q.targets_from_stdin);
}

class DeckParse : public ::testing::Test {
 protected:
  void SetUp() override {
    tmp.write("meshes/body.geo", "// stands in for a gmsh source\n");
    tmp.write("decks/body.msh", "");
  }
  TempFolder tmp;
};

TEST_F(DeckParse, ReadsEveryKey) {
  const std::string path = tmp.write("decks/full.yaml", kFullDeck);
  const Config c = parse_deck(path);
  EXPECT_EQ(c.deck_path, path);
  EXPECT_EQ(c.deck_name, "full");
  // Resolved from the deck's folder, not from the working directory.
  EXPECT_EQ(c.mesh.file, (tmp.path() / "meshes/body.geo").string());
  EXPECT_EQ(c.mesh.order, 2);
  EXPECT_EQ(c.mesh.parameters, (std::map<std::string, double>{{"h", 0.05}, {"a", 1.5}}));
  EXPECT_EQ(c.mesh.refine, 1);
  EXPECT_TRUE(c.mesh.trust_geo);
  EXPECT_EQ(c.mesh.max_elements, 5000000);
  EXPECT_EQ(c.mesh.deck_dir, (tmp.path() / "decks").string());  // where a .geo may read too

  ASSERT_EQ(c.materials.size(), 4u);
  EXPECT_EQ(c.materials[0].law->name(), "neo_hookean");
  EXPECT_EQ(c.materials[0].density, 1100);
  EXPECT_EQ(c.materials[1].density, 0);  // default
  EXPECT_EQ(mooney_rivlin(c.materials[2]).c1(), 4000);
  EXPECT_EQ(mooney_rivlin(c.materials[2]).c2(), 1000);
  EXPECT_EQ(c.materials[3].law->name(), "gent");
  EXPECT_EQ(gent(c.materials[3]).Jm(), 25);
  EXPECT_EQ(elastic(c.materials[3]).mu, 2.0e4);

  ASSERT_EQ(c.dirichlet.size(), 3u);
  EXPECT_EQ(c.dirichlet[0].components, (std::array<bool, 3>{true, true, true}));
  EXPECT_EQ(c.dirichlet[0].value, (std::array<double, 3>{0, 0, 0}));
  EXPECT_TRUE(c.dirichlet[0].scaled);
  EXPECT_EQ(c.dirichlet[1].components, (std::array<bool, 3>{true, false, true}));
  EXPECT_EQ(c.dirichlet[1].value, (std::array<double, 3>{0.5, 0, -0.25}));
  EXPECT_FALSE(c.dirichlet[1].scaled);
  EXPECT_TRUE(c.dirichlet[2].exact);

  EXPECT_EQ(c.gravity, (std::array<double, 3>{0, -9.81, 0.5}));
  ASSERT_EQ(c.pressures.size(), 2u);
  EXPECT_EQ(c.pressures[0].group, "inner");
  EXPECT_EQ(c.pressures[0].value, 2500);
  EXPECT_EQ(c.pressures[1].value, -10);

  EXPECT_EQ(c.time.type, TimeType::quasi_static);
  EXPECT_EQ(c.time.schedule, (std::vector<double>{0.25, 0.5, 1.0, 0.75}));
  EXPECT_EQ(c.time.steps, 4);  // from the schedule
  EXPECT_EQ(c.time.max_cutbacks, 3);

  EXPECT_EQ(c.solver.preset, SolverPreset::gamg);
  const std::map<std::string, std::string> options = {{"snes_rtol", "1e-10"},
                                                      {"ksp_type", "cg"},
                                                      {"snes_monitor", ""},
                                                      {"pc_gamg_threshold", "0.02"}};
  EXPECT_EQ(c.solver.petsc_options, options);
  EXPECT_EQ(c.output.folder, "results/run1");
  EXPECT_EQ(c.output.every, 2);
  ASSERT_NE(c.exact.type, nullptr);
  EXPECT_EQ(c.exact.type->name, "lame_sphere");
  EXPECT_EQ(c.exact.parameters, (std::map<std::string, double>{{"a", 1}, {"b", 2}, {"p", 2500}}));
}

TEST_F(DeckParse, FillsDefaults) {
  const std::string path =
      tmp.write("decks/minimal.yaml",
                "mesh: {file: body.msh}\n"
                "materials: [{group: body, model: linear_elastic, E: 1, nu: 0}]\n");
  const Config c = parse_deck(path);
  const Config defaults;
  EXPECT_EQ(c.mesh.order, 1);
  EXPECT_FALSE(c.mesh.trust_geo);
  EXPECT_EQ(c.mesh.max_elements, 20'000'000);
  EXPECT_TRUE(c.dirichlet.empty());
  EXPECT_TRUE(c.pressures.empty());
  EXPECT_EQ(c.gravity, (std::array<double, 3>{0, 0, 0}));
  EXPECT_EQ(c.time.type, TimeType::static_);
  EXPECT_EQ(c.time.steps, 1);
  EXPECT_EQ(c.time.max_cutbacks, defaults.time.max_cutbacks);
  EXPECT_EQ(c.solver.preset, SolverPreset::mumps);
  EXPECT_EQ(c.output.folder, "out/minimal");  // relative to the working directory
  EXPECT_EQ(c.output.every, 1);
  EXPECT_EQ(c.exact.type, nullptr);  // exact.type none
  EXPECT_TRUE(c.cavities.empty());
  EXPECT_TRUE(c.states.empty());  // one implicit state, the load ramp over time.steps
  EXPECT_FALSE(c.tip.has_value());
  EXPECT_FALSE(c.control.has_value());
}

TEST_F(DeckParse, ReadsCavitiesStatesAndTip) {
  const Config c = parse_deck(tmp.write("decks/cavities.yaml", kCavityDeck));
  ASSERT_EQ(c.cavities.size(), 7u);

  const auto& hydraulic = c.cavities[0];
  EXPECT_EQ(hydraulic.group, "cavity");
  EXPECT_EQ(hydraulic.kind, hs::CavityKind::hydraulic);
  EXPECT_EQ(hydraulic.added_volume, 1.5e-5);
  EXPECT_EQ(hydraulic.pressure, 0);     // an unknown of the run when the volume is given
  EXPECT_EQ(hydraulic.density, 13600);  // mercury
  EXPECT_EQ(hydraulic.fluid_weight.method, hs::WeightMethod::column);
  EXPECT_EQ(hydraulic.fluid_weight.grid, 64);
  EXPECT_EQ(hydraulic.fluid_weight.device, hs::WeightDevice::cuda);
  EXPECT_EQ(hydraulic.fluid_weight.coupling, hs::WeightCoupling::linearized);

  EXPECT_EQ(c.cavities[1].kind, hs::CavityKind::pneumatic);
  EXPECT_EQ(c.cavities[1].pressure, 2.0e3);
  EXPECT_FALSE(c.cavities[1].added_volume.has_value());

  // No control at all: an open cavity at gauge pressure 0.
  const auto& open = c.cavities[2];
  EXPECT_EQ(open.kind, hs::CavityKind::pneumatic);
  EXPECT_EQ(open.pressure, 0);
  EXPECT_FALSE(open.added_volume.has_value());
  EXPECT_EQ(open.density, 0);

  EXPECT_EQ(c.cavities[3].kind, hs::CavityKind::sealed_gas);
  EXPECT_EQ(c.cavities[3].initial_pressure, -5.0e3);
  EXPECT_EQ(c.cavities[3].atmospheric_pressure, 1.0e5);
  EXPECT_EQ(c.cavities[4].kind, hs::CavityKind::sealed_volume);
  // A sealed gas without its keys: gauge 0 at the mesh's volume, standard atmosphere.
  EXPECT_EQ(c.cavities[6].initial_pressure, 0);
  EXPECT_EQ(c.cavities[6].atmospheric_pressure, 101325);

  // Hydraulic defaults: a weightless liquid; the fluid-weight keys not given keep theirs (the
  // closed form, exact for a full cavity).
  const auto& water = c.cavities[5];
  EXPECT_EQ(water.density, 0);
  EXPECT_EQ(water.fluid_weight.method, hs::WeightMethod::hydrostatic);
  EXPECT_EQ(water.fluid_weight.device, hs::WeightDevice::cpu);
  EXPECT_EQ(water.fluid_weight.coupling, hs::WeightCoupling::converged);

  ASSERT_EQ(c.states.size(), 3u);
  EXPECT_EQ(c.states[0].name, "rest");
  EXPECT_EQ(c.states[0].steps, 4);
  EXPECT_TRUE(c.states[0].cavities.empty());
  EXPECT_EQ(c.time.steps, 4);  // the first state's steps replace time.steps
  EXPECT_EQ(c.time.max_cutbacks, 4);
  EXPECT_EQ(c.states[1].name, "inflated");
  EXPECT_EQ(c.states[1].steps, 10);
  ASSERT_EQ(c.states[1].cavities.size(), 2u);
  EXPECT_EQ(c.states[1].cavities.at("cavity").added_volume, 3.0e-5);
  EXPECT_FALSE(c.states[1].cavities.at("cavity").pressure.has_value());
  EXPECT_EQ(c.states[1].cavities.at("bladder").pressure, 5.0e3);
  EXPECT_FALSE(c.states[1].cavities.at("bladder").added_volume.has_value());
  EXPECT_EQ(c.states[2].name, "hold");
  EXPECT_EQ(c.states[2].steps, 1);  // default
  EXPECT_TRUE(c.states[2].cavities.empty());

  ASSERT_TRUE(c.tip.has_value());
  EXPECT_EQ(c.tip->group, "tip");
}

TEST_F(DeckParse, CavitiesWithoutStates) {
  // Cavities alone: one implicit state, their controls ramped with the load over time.steps.
  const Config c = parse_deck(tmp.write("decks/one_state.yaml", R"(mesh: {file: body.msh}
materials: [{group: body, model: neo_hookean, E: 1.0e5, nu: 0.45}]
cavities: [{group: cavity, added_volume: -1.0e-6}]
time: {steps: 6}
)"));
  ASSERT_EQ(c.cavities.size(), 1u);
  EXPECT_EQ(c.cavities[0].kind, hs::CavityKind::pneumatic);
  EXPECT_EQ(c.cavities[0].added_volume, -1.0e-6);  // a negative added volume deflates
  EXPECT_TRUE(c.states.empty());
  EXPECT_EQ(c.time.steps, 6);
  EXPECT_FALSE(c.tip.has_value());
}

TEST_F(DeckParse, ReadsControl) {
  const Config c = parse_deck(tmp.write("decks/control.yaml", kControlDeck));
  ASSERT_TRUE(c.control.has_value());
  const ControlConfig& control = *c.control;

  ASSERT_EQ(control.effectors.size(), 2u);
  const auto& tip = control.effectors[0];
  EXPECT_EQ(tip.name, "tip");
  EXPECT_EQ(tip.point, "effector");
  EXPECT_EQ(tip.directions, (std::array<bool, 3>{true, false, true}));
  EXPECT_EQ(tip.weight, 2.5);
  const auto& side = control.effectors[1];
  EXPECT_EQ(side.name, "side");
  EXPECT_EQ(side.point, "");  // a material point: its position is used
  EXPECT_EQ(side.position, (std::array<double, 3>{0.045, 0.009, -0.25e-3}));
  EXPECT_EQ(side.directions, (std::array<bool, 3>{true, true, true}));  // default: all
  EXPECT_EQ(side.weight, 1);

  ASSERT_EQ(control.actuators.size(), 2u);
  const auto& upper = control.actuators[0];
  EXPECT_EQ(upper.constraint, "upper");
  EXPECT_EQ(upper.min_multiplier, -1.5e3);
  EXPECT_EQ(upper.max_multiplier, 2.0e4);
  EXPECT_EQ(upper.min_measure_change, -1.0e-6);
  EXPECT_EQ(upper.max_measure_change, 2.0e-5);
  EXPECT_EQ(upper.max_multiplier_step, 2000);
  // Equal bounds hold the pressure; the bounds not given are none.
  const auto& lower = control.actuators[1];
  EXPECT_EQ(lower.constraint, "lower");
  EXPECT_EQ(lower.min_multiplier, 0);
  EXPECT_EQ(lower.max_multiplier, 0);
  EXPECT_EQ(lower.min_measure_change, -1e300);
  EXPECT_EQ(lower.max_measure_change, 1e300);
  EXPECT_EQ(lower.max_multiplier_step, 1e300);

  // Target sets in order, each with its effectors in the deck's order.
  ASSERT_EQ(control.targets.size(), 3u);
  ASSERT_EQ(control.targets[0].size(), 1u);
  EXPECT_EQ(control.targets[0][0].effector, "tip");
  EXPECT_EQ(control.targets[0][0].position, (std::array<double, 3>{0.09, 0.0, -0.01}));
  ASSERT_EQ(control.targets[1].size(), 2u);
  EXPECT_EQ(control.targets[1][0].effector, "side");
  EXPECT_EQ(control.targets[1][0].position, (std::array<double, 3>{0.05, 0.01, 0.0}));
  EXPECT_EQ(control.targets[1][1].effector, "tip");
  EXPECT_EQ(control.targets[1][1].position, (std::array<double, 3>{0.08, 0.0, 0.02}));
  ASSERT_EQ(control.targets[2].size(), 2u);  // a block map reads like a flow map
  EXPECT_EQ(control.targets[2][0].effector, "tip");
  EXPECT_EQ(control.targets[2][1].effector, "side");
  EXPECT_EQ(control.targets[2][1].position, (std::array<double, 3>{0.044, 0.009, 0.003}));

  EXPECT_EQ(control.steps_per_target, 25);
  EXPECT_EQ(control.regularization, 0);
  EXPECT_TRUE(control.newton_finish);
  EXPECT_EQ(control.free_solve, hs::FreeSolve::one_step);
  EXPECT_FALSE(control.targets_from_stdin);  // only the command line sets it
  // Control leaves the rest of the run as it was.
  EXPECT_EQ(c.cavities.size(), 3u);
  EXPECT_EQ(c.states.size(), 1u);
  EXPECT_EQ(c.time.steps, 3);
}

TEST_F(DeckParse, ControlDefaults) {
  const Config c = parse_deck(tmp.write("decks/control.yaml", kMinimalControlDeck));
  ASSERT_TRUE(c.control.has_value());
  const ControlConfig defaults;
  const ActuatorConfig unbounded;
  ASSERT_EQ(c.control->effectors.size(), 1u);
  EXPECT_EQ(c.control->effectors[0].directions, (std::array<bool, 3>{true, true, true}));
  EXPECT_EQ(c.control->effectors[0].weight, 1);
  ASSERT_EQ(c.control->actuators.size(), 1u);
  const auto& a = c.control->actuators[0];
  EXPECT_EQ(a.min_multiplier, unbounded.min_multiplier);
  EXPECT_EQ(a.max_multiplier, 2.0e4);
  EXPECT_EQ(a.min_measure_change, unbounded.min_measure_change);
  EXPECT_EQ(a.max_measure_change, unbounded.max_measure_change);
  EXPECT_EQ(a.max_multiplier_step, unbounded.max_multiplier_step);
  EXPECT_TRUE(c.control->targets.empty());  // none in the deck (e.g. from the command line)
  EXPECT_EQ(c.control->steps_per_target, 10);
  EXPECT_EQ(c.control->regularization, 1e-3);
  EXPECT_EQ(c.control->regularization, defaults.regularization);
  EXPECT_FALSE(c.control->newton_finish);
  EXPECT_EQ(c.control->free_solve, hs::FreeSolve::newton);
  EXPECT_FALSE(c.control->targets_from_stdin);
}

TEST_F(DeckParse, PrintedControlSetsOnlyItsBounds) {
  const Config c = parse_deck(tmp.write("decks/control.yaml", kMinimalControlDeck));
  const std::string printed = format_config(c);
  EXPECT_NE(printed.find("max_pressure: 20000"), std::string::npos) << printed;
  for (const char* unset : {"min_pressure", "volume_growth", "max_pressure_change", "1e+300",
                            "targets", "targets_from_stdin"})
    EXPECT_EQ(printed.find(unset), std::string::npos) << unset << "\n" << printed;
  // The defaults are printed.
  for (const char* key : {"directions: [x, y, z]", "weight: 1", "steps_per_target: 10",
                          "regularization: 0.001", "newton_finish: false"})
    EXPECT_NE(printed.find(key), std::string::npos) << key << "\n" << printed;
}

TEST_F(DeckParse, RoundTripThroughFormatConfig) {
  for (const char* text :
       {kFullDeck, kDynamicDeck, kCavityDeck, kControlDeck, kMinimalControlDeck}) {
    const Config first = parse_deck(tmp.write("decks/deck.yaml", text));
    // Written elsewhere: the printed mesh path is absolute, so the copy reads the same mesh.
    const std::string printed = format_config(first);
    const Config second = parse_deck(tmp.write("elsewhere/deck.yaml", printed));
    SCOPED_TRACE(printed);
    expect_same(first, second);
    // The same text, but for the "# deck:" line.
    const std::string again = format_config(second);
    EXPECT_EQ(again.substr(again.find('\n')), printed.substr(printed.find('\n')));
  }
}

// The printout leaves out what the deck may not say: an .h5 mesh keeps its order (the
// printout used to give mesh.order, which the reader refuses for an .h5), and a .GEO is a
// .geo (its parameters, refine and trust_geo used to be left out, and read back as defaults).
TEST_F(DeckParse, PrintoutsOfH5AndUpperCaseGeoMeshesReadBack) {
  tmp.write("decks/body.h5", "");
  tmp.write("decks/body.GEO", "");
  const std::string materials = "materials: [{group: body, model: neo_hookean, E: 1, nu: 0.3}]\n";
  for (const std::string mesh :
       {"mesh: {file: body.h5}\n", "mesh: {file: body.GEO, parameters: {h: 0.1}, refine: 1}\n"}) {
    const Config first = parse_deck(tmp.write("decks/deck.yaml", mesh + materials));
    const std::string printed = format_config(first);
    SCOPED_TRACE(printed);
    Config second;
    ASSERT_NO_THROW(second = parse_deck(tmp.write("elsewhere/deck.yaml", printed)));
    expect_same(first, second);
  }
}

// A subnormal is a finite number: the deck reads it as it is (the interactive mode's target
// lines refused it once, docs/reliability.md), from the file and from an override.
TEST_F(DeckParse, SubnormalNumbersAreRead) {
  const std::string path = tmp.write("decks/tiny.yaml", R"(mesh: {file: body.msh}
materials:
  - {group: body, model: linear_elastic, E: 1.0e6, nu: 0.3, density: 1000}
boundary:
  - {group: clamp, value: [1e-320, -5e-324, 0]}
)");
  const Config c = parse_deck(path, {"loads.gravity=[0, 1e-320, -9.81]"});
  EXPECT_EQ(c.dirichlet[0].value[0], 1e-320);
  EXPECT_EQ(c.dirichlet[0].value[1], -5e-324);
  EXPECT_EQ(c.gravity[1], 1e-320);
}

TEST_F(DeckParse, DynamicDefaults) {
  const Config c = parse_deck(tmp.write("decks/dyn.yaml", kDynamicDeck));
  EXPECT_EQ(c.time.type, TimeType::dynamic);
  EXPECT_EQ(c.time.dt, 0.01);
  EXPECT_EQ(c.time.end_time, 0.5);
  EXPECT_EQ(c.time.integrator, Integrator::newmark);
  EXPECT_EQ(c.time.newmark_beta, 0.3025);
  EXPECT_EQ(c.time.newmark_gamma, 0.6);
}

// mu = E / (2 (1 + nu)), lambda = E nu / ((1 + nu)(1 - 2 nu)), and the inverse.
TEST_F(DeckParse, ElasticConstantConversion) {
  const std::string path = tmp.write("decks/pairs.yaml", R"(mesh: {file: body.msh}
materials:
  - {group: a, model: linear_elastic, E: 1.0e6, nu: 0.25}
  - {group: b, model: neo_hookean, E: 2.98e5, nu: 0.49}
  - {group: c, model: linear_elastic, mu: 3.0e5, lambda: -1.5e5}
  - {group: d, model: mooney_rivlin, mu: 1.0e5, lambda: 2.0e5}
)");
  const Config c = parse_deck(path);
  // E = 1e6, nu = 1/4: mu = 1e6 / 2.5 = 4e5, lambda = 2.5e5 / (1.25 * 0.5) = 4e5.
  EXPECT_DOUBLE_EQ(elastic(c.materials[0]).mu, 4.0e5);
  EXPECT_DOUBLE_EQ(elastic(c.materials[0]).lambda, 4.0e5);
  const double E = 2.98e5, nu = 0.49;
  EXPECT_DOUBLE_EQ(elastic(c.materials[1]).mu, E / (2 * (1 + nu)));
  EXPECT_DOUBLE_EQ(elastic(c.materials[1]).lambda, E * nu / ((1 + nu) * (1 - 2 * nu)));
  // mu = 3e5, lambda = -1.5e5: nu = lambda / (2 (lambda + mu)) = -0.5, E = 2 mu (1 + nu) = 3e5.
  EXPECT_DOUBLE_EQ(elastic(c.materials[2]).nu, -0.5);
  EXPECT_DOUBLE_EQ(elastic(c.materials[2]).E, 3.0e5);
  // Given mu, lambda: the derived E, nu satisfy the forward formulas.
  for (const auto& m : {elastic(c.materials[2]), elastic(c.materials[3])}) {
    EXPECT_NEAR(m.E / (2 * (1 + m.nu)), m.mu, 1e-12 * m.mu);
    EXPECT_NEAR(m.E * m.nu / ((1 + m.nu) * (1 - 2 * m.nu)), m.lambda, 1e-12 * std::abs(m.lambda));
  }
  // Mooney-Rivlin defaults: c1 = mu / 2, c2 = 0 (small-strain shear modulus 2 (c1 + c2) = mu).
  EXPECT_DOUBLE_EQ(mooney_rivlin(c.materials[3]).c1(), 0.5e5);
  EXPECT_EQ(mooney_rivlin(c.materials[3]).c2(), 0);
}

// formulation: auto takes F-bar on P2 at nu >= 0.49 (kappa/mu >= 49.7) and the displacement
// element otherwise; P1 at nu >= 0.49 warns with the locking error to expect; the choice and
// its reason are printed beside the material and read back as asked.
TEST_F(DeckParse, ElementFormulationIsResolvedAndPrinted) {
  const std::string path = tmp.write("decks/silicone.yaml", R"(mesh: {file: body.msh, order: 2}
materials:
  - {group: a, model: neo_hookean, E: 2.0e5, nu: 0.4999}
  - {group: b, model: neo_hookean, E: 2.0e5, nu: 0.489}
  - {group: c, model: yeoh, C1: 1.1e5, nu: 0.49}
  - {group: d, model: neo_hookean, E: 2.0e5, nu: 0.4999, formulation: displacement}
)");
  const Config c = parse_deck(path);
  const auto fbar = ElementFormulation::fbar, displacement = ElementFormulation::displacement;
  EXPECT_EQ(c.materials[0].element, fbar);
  EXPECT_EQ(c.materials[0].formulation_reason, "auto: nu = 0.4999 >= 0.49 on P2");
  EXPECT_EQ(c.materials[1].element, displacement);
  EXPECT_EQ(c.materials[1].formulation_reason, "auto: nu = 0.489 < 0.49 on P2");
  EXPECT_EQ(c.materials[2].element, fbar);
  EXPECT_EQ(c.materials[3].element, displacement);
  EXPECT_EQ(c.materials[3].formulation_reason, "asked, nu = 0.4999 >= 0.49 on P2");
  for (const auto& m : c.materials) EXPECT_EQ(m.formulation_warning, "") << m.group;
  const std::string printed = format_config(c);
  const size_t first = printed.find("formulation: auto  # ");
  ASSERT_NE(first, std::string::npos) << printed;
  const size_t element = printed.find("; element: ", first);
  EXPECT_EQ(printed.substr(element, printed.find('\n', element) - element),
            "; element: fbar (auto: nu = 0.4999 >= 0.49 on P2)")
      << printed;
  const Config back = parse_deck(tmp.write("decks/printed.yaml", printed));
  for (size_t i = 0; i < c.materials.size(); ++i)
    EXPECT_EQ(back.materials[i].element, c.materials[i].element) << i;

  // P1: the nodal-pressure element where the law has a volumetric term; forcing the
  // displacement element warns with the error to expect; a law without the term warns too.
  const Config p1 = parse_deck(path, {"mesh.order=1"});
  const auto nodal = ElementFormulation::nodal_pressure;
  EXPECT_EQ(p1.materials[0].element, nodal);
  EXPECT_EQ(p1.materials[0].formulation_reason, "auto: nu = 0.4999 >= 0.49 on P1");
  EXPECT_EQ(p1.materials[1].element, displacement);
  EXPECT_EQ(p1.materials[2].element, nodal);
  EXPECT_EQ(p1.materials[3].element, displacement);
  for (int i : {0, 1, 2}) EXPECT_EQ(p1.materials[i].formulation_warning, "") << i;
  EXPECT_NE(p1.materials[3].formulation_warning.find(
                "P1 displacement elements lock at nu = 0.4999: a thick sphere inflated by "
                "pressure comes out about 86 % too stiff"),
            std::string::npos)
      << p1.materials[3].formulation_warning;
  const Config svk =
      parse_deck(path, {"mesh.order=1", "materials[0].model=saint_venant_kirchhoff"});
  EXPECT_EQ(svk.materials[0].element, displacement);
  EXPECT_NE(svk.materials[0].formulation_warning.find("this law has no volumetric term"),
            std::string::npos)
      << svk.materials[0].formulation_warning;
}

// An element that cannot run where it is asked for is refused, naming the one that can.
TEST_F(DeckParse, ElementFormulationThatCannotRunIsRefused) {
  const std::string path = tmp.write("decks/forced.yaml", R"(mesh: {file: body.msh, order: 1}
materials:
  - {group: a, model: neo_hookean, E: 2.0e5, nu: 0.4999}
)");
  auto error_of = [&](std::vector<std::string> overrides) {
    try {
      parse_deck(path, overrides);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error_of({"materials[0].formulation=fbar"})
                .find("nodal_pressure is the locking-free element of P1"),
            std::string::npos);
  EXPECT_NE(error_of({"materials[0].formulation=nodal_pressure", "mesh.order=2"})
                .find("nodal_pressure needs mesh.order: 1"),
            std::string::npos);
  EXPECT_NE(
      error_of(
          {"materials[0].formulation=nodal_pressure", "materials[0].model=saint_venant_kirchhoff"})
          .find("materials[0].formulation: nodal_pressure needs a law with a volumetric term"),
      std::string::npos)
      << error_of({"materials[0].formulation=nodal_pressure",
                   "materials[0].model=saint_venant_kirchhoff"});
  EXPECT_EQ(error_of({"materials[0].formulation=nodal_pressure"}), "no error");
}

TEST_F(DeckParse, OverridesChangeTheTreeBeforeValidation) {
  const std::string path = tmp.write("decks/base.yaml", R"(mesh: {file: ../meshes/body.geo}
materials:
  - {group: body, model: linear_elastic, E: 1.0e6, nu: 0.25}
)");
  const Config c = parse_deck(
      path, {"mesh.order=2", "mesh.parameters.h=0.05", "materials[0].E=2e6",
             "solver.petsc_options.ksp_type=cg", "loads.gravity=[0, 0, -9.81]", "time.type=dynamic",
             "time.dt=0.1", "time.end_time=1", "output.folder=elsewhere"});
  EXPECT_EQ(c.mesh.order, 2);
  EXPECT_EQ(c.mesh.parameters.at("h"), 0.05);
  EXPECT_EQ(elastic(c.materials[0]).E, 2e6);
  EXPECT_DOUBLE_EQ(elastic(c.materials[0]).mu, 8e5);  // derived from the overridden E
  EXPECT_EQ(c.solver.petsc_options.at("ksp_type"), "cg");
  EXPECT_EQ(c.gravity, (std::array<double, 3>{0, 0, -9.81}));
  EXPECT_EQ(c.time.type, TimeType::dynamic);
  EXPECT_EQ(c.time.dt, 0.1);
  EXPECT_EQ(c.output.folder, "elsewhere");
  // A later override of the same key wins.
  EXPECT_EQ(parse_deck(path, {"mesh.order=2", "mesh.order=1"}).mesh.order, 1);
}

std::string error_of(const std::string& path, const std::vector<std::string>& overrides) {
  try {
    parse_deck(path, overrides);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST_F(DeckParse, BadOverridesFailNamingThem) {
  const std::string path = tmp.write("decks/base.yaml", R"(mesh: {file: ../meshes/body.geo}
materials:
  - {group: body, model: linear_elastic, E: 1.0e6, nu: 0.25}
)");
  struct Case {
    std::string override_text, reason;
  };
  const std::vector<Case> cases = {
      {"mesh.order", "expected key=value"},
      {"mesh..order=2", "malformed key"},
      {"materials[x].E=2", "malformed key"},
      {"materials[1].E=2", "materials[1] does not exist (materials has 1 entries)"},
      {"mesh.file.name=2", "mesh.file is not a map"},
      {"mesh[0]=2", "mesh is not a list"},
      {"mesh.order=[1, 2", "the value is not valid YAML"},
      // Well-formed overrides whose result fails validation name the override as well.
      {"mesh.ordr=2", "mesh.ordr: unknown key (did you mean 'order'?"},
      {"materials[0].nu=0.6",
       "materials[0].nu: must lie in (-1, 0.5] (0.5: incompressible), got 0.6"},
      {"mesh.order=two", "mesh.order: expected an integer, got 'two'"},
  };
  for (const auto& c : cases) {
    const std::string message = error_of(path, {c.override_text});
    EXPECT_NE(message.find(path + ": "), std::string::npos) << message;
    EXPECT_NE(message.find(c.reason), std::string::npos) << message;
    EXPECT_NE(message.find("override '" + c.override_text + "'"), std::string::npos) << message;
  }
}

TEST_F(DeckParse, OverridesReachCavitiesAndStates) {
  const std::string path = tmp.write("decks/cavity.yaml", R"(mesh: {file: body.msh}
materials: [{group: body, model: neo_hookean, E: 1.0e5, nu: 0.45}]
cavities: [{group: cavity, pressure: 1000}]
states:
  - {name: rest}
  - {name: inflated, cavities: {cavity: {pressure: 2000}}}
)");
  const Config c = parse_deck(path, {"cavities[0].kind=hydraulic", "cavities[0].density=1000",
                                     "states[1].cavities.cavity.pressure=3000"});
  EXPECT_EQ(c.cavities[0].kind, hs::CavityKind::hydraulic);
  EXPECT_EQ(c.cavities[0].density, 1000);
  EXPECT_EQ(c.states[1].cavities.at("cavity").pressure, 3000);
  const std::string message = error_of(path, {"cavities[0].density=-1"});
  EXPECT_NE(message.find(path + ": cavities[0].density: only used by kind hydraulic"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("override 'cavities[0].density=-1'"), std::string::npos) << message;
}

TEST_F(DeckParse, OverridesReachControl) {
  const std::string path = tmp.write("decks/control.yaml", kControlDeck);
  const Config c = parse_deck(
      path, {"control.regularization=1e-2", "control.targets[0].tip=[0.07, 0, 0.03]",
             "control.actuators[1].max_pressure=1000", "control.effectors[0].directions=[y]"});
  EXPECT_EQ(c.control->regularization, 1e-2);
  EXPECT_EQ(c.control->targets[0][0].position, (std::array<double, 3>{0.07, 0, 0.03}));
  EXPECT_EQ(c.control->actuators[1].max_multiplier, 1000);
  EXPECT_EQ(c.control->effectors[0].directions, (std::array<bool, 3>{false, true, false}));
  const std::string message = error_of(path, {"control.actuators[0].max_pressure=-2000"});
  EXPECT_NE(message.find(path + ": control.actuators[0].min_pressure: is -1500 but max_pressure is "
                                "-2000"),
            std::string::npos)
      << message;
}

// The decks shipped with the repository stay valid as the format evolves.
TEST(RepositoryDecks, AllParseAndRoundTrip) {
  namespace fs = std::filesystem;
  int count = 0;
  for (const char* folder : {"input", "bench/fem"}) {
    for (const auto& entry : fs::directory_iterator(fs::path(HYDROSOFT_SOURCE_DIR) / folder)) {
      if (entry.path().extension() != ".yaml") continue;
      SCOPED_TRACE(entry.path().string());
      const Config c = parse_deck(entry.path().string());
      EXPECT_EQ(c.output.folder, "out/" + entry.path().stem().string());
      TempFolder tmp;
      expect_same(c, parse_deck(tmp.write("printed.yaml", format_config(c))));
      ++count;
    }
  }
  EXPECT_GT(count, 0);
}

// The examples of docs/decks.md are valid decks: the cavity example, the cables and the
// obstacles sections (each with the control example), the dynamic states example, the control
// example, and the complete example, also with its dynamic time section.
TEST(DocumentedExample, Parses) {
  std::ifstream in(std::string(HYDROSOFT_SOURCE_DIR) + "/docs/decks.md");
  std::stringstream text;
  text << in.rdbuf();
  std::vector<std::string> blocks;
  const std::string doc = text.str(), open = "```yaml\n", close = "```\n";
  for (size_t at = doc.find(open); at != std::string::npos; at = doc.find(open, at)) {
    at += open.size();
    const size_t end = doc.find(close, at);
    blocks.push_back(doc.substr(at, end - at));
  }
  ASSERT_EQ(blocks.size(), 7u);
  TempFolder tmp;
  tmp.write("meshes/lame_sphere.geo", "");
  tmp.write("meshes/cylinder.geo", "");
  tmp.write("meshes/finger.geo", "");
  // The cavity and control examples are decks of their own.
  const Config cavity = parse_deck(tmp.write("input/cavity.yaml", blocks[0]));
  ASSERT_EQ(cavity.states.size(), 2u);
  EXPECT_EQ(cavity.states[1].cavities.at("cavity").added_volume, 1.5e-5);
  EXPECT_EQ(cavity.time.steps, 4);
  // The dynamic states example, a deck too: a ramp, then a step at the same time.
  const Config in_time = parse_deck(tmp.write("input/dynamic.yaml", blocks[1]));
  ASSERT_EQ(in_time.states.size(), 3u);
  EXPECT_EQ(in_time.states[0].time, 0.0);
  EXPECT_EQ(in_time.states[1].time, 0.1);
  EXPECT_EQ(in_time.states[2].time, 0.1);
  EXPECT_EQ(state_time_steps(in_time.states, in_time.time.dt), (std::vector<int64_t>{0, 200, 201}));
  blocks.erase(blocks.begin() + 1);
  // The cables example is a section: it joins the control example's deck.
  const std::string cables = blocks[1], obstacles = blocks[2];
  blocks.erase(blocks.begin() + 1, blocks.begin() + 3);
  const Config control = parse_deck(tmp.write("input/control.yaml", blocks[1]));
  const Config with_cable = parse_deck(tmp.write("input/cable.yaml", blocks[1] + cables));
  ASSERT_EQ(with_cable.cables.size(), 1u);
  EXPECT_EQ(with_cable.cables[0].points.size(), 4u);
  EXPECT_EQ(with_cable.cables[0].pull_point->at(0), -0.02);
  const Config touching = parse_deck(tmp.write("input/obstacles.yaml", blocks[1] + obstacles));
  ASSERT_EQ(touching.obstacles.size(), 4u);
  EXPECT_EQ(touching.obstacles[1].type, ObstacleType::sphere);
  EXPECT_EQ(touching.obstacles[1].move[2], -0.01);
  EXPECT_EQ(touching.obstacles[3].axis[0], 1.0);
  EXPECT_EQ(*touching.contact.distance, 1.0e-4);
  ASSERT_TRUE(control.control.has_value());
  EXPECT_EQ(control.control->effectors[0].point, "effector");
  EXPECT_EQ(control.control->actuators[0].max_measure_change, 2.0e-5);
  ASSERT_EQ(control.control->targets.size(), 2u);
  EXPECT_EQ(control.control->targets[1][0].position, (std::array<double, 3>{0.08, 0.0, 0.02}));
  blocks.erase(blocks.begin(), blocks.begin() + 2);
  const Config c = parse_deck(tmp.write("input/example.yaml", blocks[0]));
  EXPECT_EQ(mooney_rivlin(c.materials[0]).c1(), 4.0e4);
  EXPECT_EQ(c.time.steps, 5);
  const size_t time = blocks[0].find("time:"), solver = blocks[0].find("solver:");
  const std::string dynamic = blocks[0].substr(0, time) + blocks[1] + blocks[0].substr(solver);
  EXPECT_EQ(parse_deck(tmp.write("input/dynamic.yaml", dynamic)).time.end_time, 0.2);
}

}  // namespace
}  // namespace hs
