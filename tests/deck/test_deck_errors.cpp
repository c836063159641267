// parse_deck on bad decks: every class of error is an InputError whose message reads
// "FILE: KEY: reason". One test per class; each case checks the file, the key and the reason.
#include <gtest/gtest.h>

#include "common/error.hpp"
#include "deck/deck.hpp"
#include "deck/exact_section.hpp"
#include "materials/registry.hpp"
#include "temp_folder.hpp"

namespace hs {
namespace {

using testing::TempFolder;

const std::string kMesh = "mesh: {file: body.geo}\n";
const std::string kMaterials =
    "materials:\n  - {group: body, model: linear_elastic, E: 1.0e6, nu: 0.3}\n";

struct Case {
  std::string deck;    // the whole deck
  std::string key;     // expected "FILE: KEY: "
  std::string reason;  // expected in the message after the key
};

class DeckErrors : public ::testing::Test {
 protected:
  void SetUp() override { tmp.write("body.geo", ""); }

  // Writes each deck, parses it, and checks the message of the InputError it must raise.
  void expect_errors(const std::vector<Case>& cases) {
    for (size_t i = 0; i < cases.size(); ++i) {
      const std::string path = tmp.write("case" + std::to_string(i) + ".yaml", cases[i].deck);
      SCOPED_TRACE(cases[i].deck);
      try {
        parse_deck(path);
        ADD_FAILURE() << "no InputError for " << cases[i].key;
      } catch (const InputError& e) {
        const std::string message = e.what();
        const std::string head = path + ": " + cases[i].key + ": ";
        EXPECT_EQ(message.rfind(head, 0), 0u) << message;
        EXPECT_NE(message.find(cases[i].reason, head.size()), std::string::npos) << message;
      }
    }
  }

  TempFolder tmp;
};

TEST_F(DeckErrors, UnknownKeysSuggestTheNearest) {
  expect_errors({
      {kMesh + kMaterials + "mesj: {}\n", "mesj", "unknown key (did you mean 'mesh'?"},
      {"mesh: {file: body.geo, ordr: 2}\n" + kMaterials, "mesh.ordr", "did you mean 'order'?"},
      {kMesh + "materials:\n  - {group: b, model: linear_elastic, E: 1, nu: 0.3}\n"
               "  - {group: c, model: linear_elastic, E: 1, Nu: 0.3}\n",
       "materials[1].Nu", "unknown key (did you mean 'nu'? valid keys: group, model, E, nu"},
      {kMesh + "materials:\n  - {group: b, model: linear_elastic, youngs: 1, nu: 0.3}\n",
       "materials[0].youngs", "unknown key (did you mean 'E'?"},
      {kMesh + "materials:\n  - {group: b, model: linear_elastic, E: 1, Poisson: 0.3}\n",
       "materials[0].Poisson", "unknown key (did you mean 'nu'?"},
      {kMesh + "materials:\n  - {group: b, model: neo_hookean, Youngs_Modulus: 1, nu: 0.3}\n",
       "materials[0].Youngs_Modulus", "unknown key (did you mean 'E'?"},
      {kMesh + "materials:\n  - {group: b, model: mooney_rivlin, E: 1, poissons_ratio: 0.3}\n",
       "materials[0].poissons_ratio", "unknown key (did you mean 'nu'?"},
      {kMesh + "materials:\n  - {group: b, model: gent, young: 1, nu: 0.3, Jm: 5}\n",
       "materials[0].young", "unknown key (did you mean 'E'?"},
      {kMesh + kMaterials + "time: {type: static, stpes: 3}\n", "time.stpes",
       "did you mean 'steps'?"},
      {kMesh + kMaterials + "loads: {gravity: [0, 0, -1], gravity: [0, 0, 1]}\n", "loads.gravity",
       "duplicate key"},
  });
}

// Found by the fuzz harness (tests/fuzz/): a carriage return inside a key was printed as it was,
// and the terminal wrote the rest of the message over its start.
TEST_F(DeckErrors, ControlCharactersOfTheDeckAreWrittenOut) {
  expect_errors({
      {kMesh + kMaterials + "tim\re: {}\n", "tim\\re", "unknown key (did you mean 'time'?"},
      {kMesh + kMaterials + "time: {type: \"st\\x1batic\"}\n", "time.type",
       "unknown name 'st\\x1batic'"},
  });
}

TEST_F(DeckErrors, WrongTypes) {
  expect_errors({
      {kMesh + "materials:\n  - {group: body, model: linear_elastic, E: stiff, nu: 0.3}\n",
       "materials[0].E", "expected a number, got 'stiff'"},
      {kMesh + "materials:\n  - {group: body, model: linear_elastic, E: \"1e6\", nu: 0.3}\n",
       "materials[0].E", "expected a number, got the string \"1e6\""},
      {"mesh: {file: body.geo, order: 1.5}\n" + kMaterials, "mesh.order",
       "expected an integer, got '1.5'"},
      {kMesh + kMaterials + "boundary:\n  - {group: base, components: x}\n",
       "boundary[0].components", "expected a list, got 'x'"},
      {kMesh + kMaterials + "loads: {gravity: [0, -9.81]}\n", "loads.gravity",
       "expected a list of 3 numbers, got 2"},
      {kMesh + kMaterials + "boundary:\n  - {group: base, value: [0, 0, 0, 1]}\n",
       "boundary[0].value", "expected a list of 3 numbers, got 4"},
      {kMesh + kMaterials + "boundary:\n  - {group: base, scaled: maybe}\n", "boundary[0].scaled",
       "expected true or false, got 'maybe'"},
      {kMesh + "materials: {group: body}\n", "materials", "expected a list, got a map"},
      {kMesh + kMaterials + "time: [static]\n", "time", "expected a map, got a list"},
      {kMesh + kMaterials + "solver: {petsc_options: {ksp_type: [cg]}}\n",
       "solver.petsc_options.ksp_type", "expected a single value"},
  });
}

TEST_F(DeckErrors, MissingRequiredKeys) {
  expect_errors({
      {kMaterials, "mesh", "required key missing"},
      {"mesh: {order: 2}\n" + kMaterials, "mesh.file", "required key missing (line 1)"},
      {kMesh, "materials", "required key missing"},
      {kMesh + "materials: []\n", "materials", "at least one material is required"},
      {kMesh + "materials:\n  - {model: linear_elastic, E: 1, nu: 0.3}\n", "materials[0].group",
       "required key missing"},
      {kMesh + "materials:\n  - {group: body, E: 1, nu: 0.3}\n", "materials[0].model",
       "required key missing"},
      {kMesh + "materials:\n  - {group: body, model: linear_elastic, E: 1}\n", "materials[0].nu",
       "required key missing"},
      {kMesh + "materials:\n  - {group: body, model: linear_elastic}\n", "materials[0]",
       "elastic constants missing: give E and nu, or mu and lambda"},
      {kMesh + "materials:\n  - {group: body, model: linear_elastic, E: 1, nu: 0.3, mu: 1}\n",
       "materials[0]", "give either E and nu or mu and lambda, not both"},
      {kMesh + kMaterials + "loads: {pressure: [{group: inner}]}\n", "loads.pressure[0].value",
       "required key missing"},
      {kMesh + kMaterials + "time: {type: dynamic, dt: 0.1}\n", "time.end_time",
       "required key missing"},
      {kMesh + kMaterials + "exact: {type: lame_sphere, parameters: {a: 1, b: 2}}\n",
       "exact.parameters.p", "required by exact solution 'lame_sphere' (takes a, b, p)"},
  });
}

TEST_F(DeckErrors, NonPhysicalValues) {
  auto material = [](const std::string& fields) {
    return kMesh + "materials:\n  - {group: body, model: neo_hookean, " + fields + "}\n";
  };
  expect_errors({
      {material("E: 0, nu: 0.3"), "materials[0].E", "must be > 0, got 0"},
      {material("E: -5, nu: 0.3"), "materials[0].E", "must be > 0, got -5"},
      {material("E: 1, nu: 0.51"), "materials[0].nu",
       "must lie in (-1, 0.5] (0.5: incompressible), got 0.51"},
      {material("E: 1, nu: -1"), "materials[0].nu",
       "must lie in (-1, 0.5] (0.5: incompressible), got -1"},
      // nu = 0.5 runs on the elements with volume multipliers, on the law's volumetric term.
      {"mesh: {file: body.geo, order: 2}\n"
       "materials:\n  - {group: body, model: linear_elastic, E: 1, nu: 0.5}\n",
       "materials[0].nu", "0.5 (exact incompressibility) on P2 needs a finite-strain law"},
      {kMesh + "materials:\n  - {group: body, model: saint_venant_kirchhoff, E: 1, nu: 0.5}\n",
       "materials[0].nu", "0.5 (exact incompressibility) needs a law with a volumetric term"},
      {material("E: 1, nu: 0.5, formulation: displacement"), "materials[0].formulation",
       "nu = 0.5 (exact incompressibility) runs on the nodal-pressure element on P1 meshes "
       "(formulation: auto or nodal_pressure); the displacement element has no volume "
       "multipliers there"},
      {material("mu: 0, lambda: 1"), "materials[0].mu", "must be > 0, got 0"},
      {material("mu: 3, lambda: -2"), "materials[0].lambda",
       "gives bulk modulus lambda + 2 mu / 3 = 0, must be > 0"},
      {material("E: 1, nu: 0.3, density: -1"), "materials[0].density", "must be >= 0, got -1"},
      {material("E: 1, nu: 0.3, density: 1e308"), "materials[0].density",
       "must be <= 1e5 kg/m^3, got 1e+308"},
      {kMesh + kMaterials + "loads: {gravity: [0, 0, -1e308]}\n", "loads.gravity",
       "each component must be within +-1e4 m/s^2, got -1e+308"},
      {kMesh + kMaterials + "time: {type: dynamic, dt: 1e-12, end_time: 4}\n", "time.dt",
       "gives 4e+12 steps of time.end_time 4, more than 1e+07"},
      {kMesh +
           "materials:\n  - {group: body, model: mooney_rivlin, E: 1, nu: 0.3, c1: 1, c2: -1}\n",
       "materials[0].c1", "c1 + c2 must be > 0"},
      {kMesh + "materials:\n  - {group: body, model: gent, E: 1, nu: 0.3, Jm: -2}\n",
       "materials[0].Jm", "must be > 0 (the limit of I1b - 3), got -2"},
      {"mesh: {file: body.geo, order: 3}\n" + kMaterials, "mesh.order", "must be 1 or 2"},
      {"mesh: {file: body.geo, refine: -1}\n" + kMaterials, "mesh.refine", "must be >= 0"},
      {kMesh + kMaterials + "time: {steps: 0}\n", "time.steps", "must be >= 1, got 0"},
      {kMesh + kMaterials + "time: {type: dynamic, dt: 0, end_time: 1}\n", "time.dt",
       "must be > 0, got 0"},
      {kMesh + kMaterials + "time: {type: dynamic, dt: 0.1, end_time: -1}\n", "time.end_time",
       "must be > 0, got -1"},
      {kMesh + kMaterials + "time: {type: quasi_static, schedule: [0.5, .nan]}\n",
       "time.schedule[1]", "must be a finite number"},
      {kMesh + kMaterials + "time: {type: quasi_static, schedule: [0.5, .inf]}\n",
       "time.schedule[1]", "must be a finite number"},
      {kMesh + kMaterials + "time: {type: dynamic, dt: 0.1, end_time: 1, newmark: {gamma: 0.4}}\n",
       "time.newmark.gamma", "must be >= 0.5"},
      {kMesh + kMaterials + "output: {every: 0}\n", "output.every", "must be >= 1"},
      {kMesh + kMaterials + "output: {checkpoint: {every: 0}}\n", "output.checkpoint.every",
       "must be >= 1 (converged steps)"},
      {kMesh + kMaterials + "output: {checkpoint: {minutes: -5}}\n", "output.checkpoint.minutes",
       "must be > 0"},
      {kMesh + kMaterials + "output: {checkpoint: {}}\n", "output.checkpoint",
       "needs every (steps) or minutes, or both"},
      {kMesh + kMaterials + "exact: {type: lame_sphere, parameters: {a: 1, b: 0.5, p: 1}}\n",
       "exact.parameters.b", "must be > a = 1, got 0.5 (exact solution 'lame_sphere') (line 4"},
      {kMesh + kMaterials + "exact: {type: cantilever_gravity, parameters: {L: -1, h: 1}}\n",
       "exact.parameters.L", "must be > 0, got -1"},
  });
}

// Its results would go to checkpoint.h5, over its checkpoint: the run ended with "status ok"
// and an .xmf naming steps the file did not hold.
TEST_F(DeckErrors, ADeckNamedCheckpointKeepsNoCheckpoints) {
  const std::string path =
      tmp.write("checkpoint.yaml", kMesh + kMaterials + "output: {checkpoint: {every: 1}}\n");
  try {
    parse_deck(path);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(
        std::string(e.what()).find(path + ": output.checkpoint: a deck named "
                                          "checkpoint.yaml writes its results to checkpoint.h5"),
        std::string::npos)
        << e.what();
  }
  EXPECT_NO_THROW(parse_deck(
      tmp.write("checkpoint2.yaml", kMesh + kMaterials + "output: {checkpoint: {every: 1}}\n")));
}

TEST_F(DeckErrors, UnknownNamesListTheValidOnes) {
  expect_errors({
      {kMesh + "materials:\n  - {group: body, model: hookean, E: 1, nu: 0.3}\n",
       "materials[0].model", "unknown name 'hookean' (valid: " + join(material_law_names()) + ")"},
      {kMesh + kMaterials + "time: {type: transient}\n", "time.type",
       "unknown name 'transient' (valid: static, quasi_static, dynamic)"},
      {kMesh + kMaterials + "time: {type: dynamic, dt: 1, end_time: 2, integrator: euler}\n",
       "time.integrator", "(valid: newmark, backward_euler)"},
      {kMesh + kMaterials + "solver: {preset: ilu}\n", "solver.preset",
       "unknown name 'ilu' (valid: mumps, gamg)"},
      {kMesh + kMaterials + "exact: {type: sphere}\n", "exact.type",
       "unknown name 'sphere' (valid: "},
      {kMesh + kMaterials + "boundary: [{group: base, components: [x, w]}]\n",
       "boundary[0].components[1]", "unknown name 'w' (valid: x, y, z)"},
  });
}

TEST_F(DeckErrors, InconsistentKeys) {
  expect_errors({
      {kMesh + "materials:\n  - {group: body, model: linear_elastic, E: 1, nu: 0.3}\n"
               "  - {group: body, model: neo_hookean, E: 2, nu: 0.3}\n",
       "materials[1].group", "duplicate material group 'body' (also in materials[0])"},
      {kMesh + "materials:\n  - {group: body, model: neo_hookean, E: 1, nu: 0.3, c1: 2}\n",
       "materials[0].c1", "only used by model mooney_rivlin"},
      {kMesh + "materials:\n  - {group: body, model: neo_hookean, E: 1, nu: 0.3, Jm: 20}\n",
       "materials[0].Jm", "only used by model gent"},
      {kMesh + "materials:\n  - {group: body, model: gent, E: 1, nu: 0.3}\n", "materials[0].Jm",
       "required key missing"},
      {kMesh + kMaterials + "time: {type: static, dt: 0.1}\n", "time.dt",
       "only used when time.type is dynamic"},
      {kMesh + kMaterials + "time: {type: dynamic, dt: 0.1, end_time: 1, steps: 3}\n", "time.steps",
       "not used when time.type is dynamic"},
      {kMesh + kMaterials + "time: {steps: 3, schedule: [0.5, 1]}\n", "time.steps",
       "is 3 but time.schedule has 2 entries"},
      {kMesh + kMaterials + "boundary: [{group: base, exact: true}]\n", "boundary[0].exact",
       "needs an exact solution, but exact.type is none"},
      {kMesh + kMaterials + "boundary: [{group: base, components: [x, x]}]\n",
       "boundary[0].components[1]", "component 'x' named twice"},
      {"mesh: {file: body.geo}\n" + kMaterials + "exact: {type: none, parameters: {a: 1}}\n",
       "exact.parameters.a", "unknown to exact solution 'none' (takes no parameters)"},
      {kMesh + "materials:\n  - {group: body, model: neo_hookean, E: 1, nu: 0.49, "
               "formulation: fbar}\n",
       "materials[0].formulation", "fbar needs mesh.order: 2"},
  });
}

TEST_F(DeckErrors, PetscOptionNames) {
  expect_errors({
      {kMesh + kMaterials + "solver: {petsc_options: {-ksp_type: cg}}\n",
       "solver.petsc_options.-ksp_type", "write PETSc options without the leading dash"},
      {kMesh + kMaterials + "solver: {petsc_options: {ksp type: cg}}\n",
       "solver.petsc_options.ksp type", "not a PETSc option name"},
  });
}

// Found by the fuzz harness (tests/fuzz/): a 5,000-character mesh.file ended in an uncaught
// std::filesystem error (exit status 4); a cantilever without gravity ran, then failed at its
// end on a NaN relative error (now refused when the run makes its exact solution, first).
TEST_F(DeckErrors, FoundByFuzzing) {
  expect_errors({
      {"mesh: {file: " + std::string(5000, 'x') + ".msh}\n" + kMaterials, "mesh.file",
       "...' not found (a relative path starts at the deck's folder; File name too long)"},
  });
  const std::string path = tmp.write(
      "cantilever.yaml",
      kMesh + kMaterials + "exact: {type: cantilever_gravity, parameters: {L: 1, h: 0.1}}\n");
  const Config config = parse_deck(path);
  try {
    make_exact_solution(config);
    ADD_FAILURE() << "no InputError for a cantilever without gravity";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path +
                                         ": loads.gravity: the cantilever_gravity solution "
                                         "needs a gravity component along z");
  }
}

TEST_F(DeckErrors, MeshFiles) {
  tmp.write("mesh.stl", "");
  tmp.write("body.msh", "");
  tmp.write("body.h5", "");
  expect_errors({
      {"mesh: {file: nowhere.msh}\n" + kMaterials, "mesh.file",
       "mesh file '" + (tmp.path() / "nowhere.msh").string() + "' not found"},
      {"mesh: {file: mesh.stl}\n" + kMaterials, "mesh.file",
       "expected a .msh, .geo or .h5 (hydrosoft mesh) file"},
      {"mesh: {file: body.h5, order: 2}\n" + kMaterials, "mesh.order",
       "an .h5 mesh keeps the order it was meshed at"},
      {"mesh: {file: body.msh, parameters: {h: 1}}\n" + kMaterials, "mesh.parameters",
       "only used with a .geo mesh file"},
      {"mesh: {file: body.msh, trust_geo: true}\n" + kMaterials, "mesh.trust_geo",
       "only used with a .geo mesh file"},
      {"mesh: {file: body.geo, trust_geo: yes please}\n" + kMaterials, "mesh.trust_geo",
       "expected true or false"},
      {"mesh: {file: body.msh, max_elements: 0}\n" + kMaterials, "mesh.max_elements",
       "must be >= 1"},
      {"mesh: {file: body.msh, max_elements: 1.5e7}\n" + kMaterials, "mesh.max_elements",
       "expected an integer"},
  });
}

TEST_F(DeckErrors, OutputFolderThatIsNotOurs) {
  tmp.write("results/notes.txt", "not hydrosoft's");
  const std::string folder = (tmp.path() / "results").string();
  expect_errors({
      {kMesh + kMaterials + "output: {folder: " + folder + "}\n", "output.folder",
       "'" + folder + "' exists and was not written by hydrosoft"},
      {kMesh + kMaterials + "output: {folder: .}\n", "output.folder", "must name a folder"},
  });
}

// The cavities, states and tip sections (docs/decks.md, "Cavities, states and tip").
const std::string kBase = kMesh + kMaterials;

std::string cavity(const std::string& fields) {
  return kBase + "cavities:\n  - {" + fields + "}\n";
}

// A hydraulic cavity "c", a sealed gas "g", a sealed volume "v", and two states whose second
// one has the given targets.
std::string targets(const std::string& map) {
  return kBase +
         "cavities:\n  - {group: c, kind: hydraulic}\n  - {group: g, kind: sealed_gas}\n"
         "  - {group: v, kind: sealed_volume}\n"
         "states:\n  - {name: rest}\n  - {name: inflated, cavities: " +
         map + "}\n";
}

TEST_F(DeckErrors, CavityKeysAndTypes) {
  expect_errors({
      {cavity("group: c, kind: hydraulic, densty: 1000"), "cavities[0].densty",
       "unknown key (did you mean 'density'?"},
      {kBase + "cavities: {group: c}\n", "cavities", "expected a list, got a map"},
      {cavity("kind: pneumatic"), "cavities[0].group", "required key missing"},
      {cavity("group: c, pressure: high"), "cavities[0].pressure", "expected a number, got 'high'"},
      {cavity("group: c, added_volume: [1]"), "cavities[0].added_volume",
       "expected a number, got a list"},
      {cavity("group: c, kind: liquid"), "cavities[0].kind",
       "unknown name 'liquid' (valid: pneumatic, hydraulic, sealed_gas, sealed_volume, "
       "pressure_limited)"},
      {cavity("group: c, kind: hydraulic, fluid_weight: column"), "cavities[0].fluid_weight",
       "expected a map, got 'column'"},
      {cavity("group: c, kind: hydraulic, fluid_weight: {grids: 3}"),
       "cavities[0].fluid_weight.grids", "did you mean 'grid'?"},
      {cavity("group: c, kind: hydraulic, fluid_weight: {method: column, grid: 1.5}"),
       "cavities[0].fluid_weight.grid", "expected an integer, got '1.5'"},
      {cavity("group: c, kind: hydraulic, fluid_weight: {method: voxel}"),
       "cavities[0].fluid_weight.method",
       "unknown name 'voxel' (valid: column, column_head, hydrostatic)"},
      {cavity("group: c, kind: hydraulic, fluid_weight: {device: gpu}"),
       "cavities[0].fluid_weight.device", "unknown name 'gpu' (valid: cpu, cuda)"},
      {cavity("group: c, kind: hydraulic, fluid_weight: {coupling: full}"),
       "cavities[0].fluid_weight.coupling", "unknown name 'full' (valid: converged, linearized)"},
      {kBase + "cavities:\n  - {group: c}\n  - {group: c, kind: sealed_volume}\n",
       "cavities[1].group", "duplicate cavity group 'c' (also in cavities[0])"},
  });
}

TEST_F(DeckErrors, CavityKeysOfOtherKinds) {
  expect_errors({
      {cavity("group: c, density: 1000"), "cavities[0].density",
       "only used by kind hydraulic (the liquid's density) (this cavity is pneumatic)"},
      {cavity("group: c, kind: sealed_gas, density: 1.2"), "cavities[0].density",
       "only used by kind hydraulic"},
      {cavity("group: c, fluid_weight: {method: column}"), "cavities[0].fluid_weight",
       "only used by kind hydraulic (how the liquid's weight reaches the walls) (this cavity is "
       "pneumatic)"},
      {cavity("group: c, kind: sealed_gas, pressure: 100"), "cavities[0].pressure",
       "only used by kinds pneumatic and hydraulic (the other kinds are not actuated) (this "
       "cavity is sealed_gas)"},
      {cavity("group: c, kind: sealed_volume, added_volume: 1e-6"), "cavities[0].added_volume",
       "only used by kinds pneumatic, hydraulic and pressure_limited (this cavity is "
       "sealed_volume)"},
      {cavity("group: c, kind: pressure_limited, max_pressure: 1e4"), "cavities[0]",
       "a pressure_limited cavity needs added_volume (the volume its pump delivers)"},
      {cavity("group: c, kind: pressure_limited, added_volume: 1e-6"), "cavities[0]",
       "a pressure_limited cavity needs max_pressure (where its relief valve opens)"},
      {cavity("group: c, kind: pressure_limited, added_volume: 1e-6, max_pressure: 0"),
       "cavities[0].max_pressure", "must be > 0"},
      {cavity("group: c, max_pressure: 1e4"), "cavities[0].max_pressure",
       "only used by kind pressure_limited (this cavity is pneumatic)"},
      {cavity("group: c, kind: pressure_limited, added_volume: 1e-6, max_pressure: 1e4, "
              "pressure: 10"),
       "cavities[0].pressure", "only used by kinds pneumatic and hydraulic"},
      {cavity("group: c, kind: hydraulic, initial_pressure: 0"), "cavities[0].initial_pressure",
       "only used by kind sealed_gas (this cavity is hydraulic)"},
      {cavity("group: c, kind: sealed_volume, atmospheric_pressure: 1e5"),
       "cavities[0].atmospheric_pressure", "only used by kind sealed_gas"},
      {cavity("group: c, kind: hydraulic, fluid_weight: {method: hydrostatic, grid: 100}"),
       "cavities[0].fluid_weight.grid", "only used by the column methods (method is hydrostatic)"},
      {cavity("group: c, kind: hydraulic, fluid_weight: {grid: 100}"),  // the default
       "cavities[0].fluid_weight.grid", "only used by the column methods (method is hydrostatic)"},
      {cavity("group: c, kind: hydraulic, fluid_weight: {method: hydrostatic, device: cuda}"),
       "cavities[0].fluid_weight.device",
       "cuda is only used by the column methods (method is hydrostatic, which runs on the cpu)"},
      {cavity("group: c, pressure: 100, added_volume: 1e-6"), "cavities[0]",
       "give either pressure or added_volume, not both"},
  });
}

TEST_F(DeckErrors, CavityNonPhysicalValues) {
  expect_errors({
      {cavity("group: c, kind: hydraulic, density: -1"), "cavities[0].density",
       "must be >= 0, got -1"},
      {cavity("group: c, kind: hydraulic, fluid_weight: {method: column, grid: 0}"),
       "cavities[0].fluid_weight.grid", "must be >= 1, got 0"},
      {cavity("group: c, kind: hydraulic, fluid_weight: {method: column, grid: 65537}"),
       "cavities[0].fluid_weight.grid", "must be <= 8192, got 65537"},
      {cavity("group: c, kind: sealed_gas, atmospheric_pressure: 0"),
       "cavities[0].atmospheric_pressure", "must be > 0, got 0"},
      {cavity("group: c, kind: sealed_gas, initial_pressure: -101325"),
       "cavities[0].initial_pressure",
       "gives the absolute pressure initial_pressure + atmospheric_pressure = 0, must be > 0"},
      {cavity("group: c, kind: sealed_gas, initial_pressure: -2e5, atmospheric_pressure: 1e5"),
       "cavities[0].initial_pressure", "= -1e+05, must be > 0"},
  });
}

TEST_F(DeckErrors, StatesAndTip) {
  expect_errors({
      {kBase + "states: {name: rest}\n", "states", "expected a list, got a map"},
      {kBase + "states: []\n", "states", "must hold at least one state"},
      {kBase + "states: [{steps: 2}]\n", "states[0].name", "required key missing"},
      {kBase + "states: [{name: \"\"}]\n", "states[0].name", "must not be empty"},
      {kBase + "states: [{name: rest, stpes: 2}]\n", "states[0].stpes", "did you mean 'steps'?"},
      {kBase + "states: [{name: rest, steps: two}]\n", "states[0].steps",
       "expected an integer, got 'two'"},
      {kBase + "states: [{name: rest}, {name: up, steps: 0}]\n", "states[1].steps",
       "must be >= 1, got 0"},
      {kBase + "states: [{name: rest}, {name: rest}]\n", "states[1].name",
       "duplicate state name 'rest' (also in states[0])"},
      {kBase + "tip: {}\n", "tip.group", "required key missing"},
      {kBase + "tip: tip\n", "tip", "expected a map, got 'tip'"},
      {kBase + "tip: {group: tip, normal: z}\n", "tip.normal", "unknown key"},
  });
}

TEST_F(DeckErrors, StateTargets) {
  expect_errors({
      {kBase + "cavities: [{group: c}]\nstates:\n  - {name: rest, cavities: {c: {pressure: "
               "1}}}\n",
       "states[0].cavities",
       "not allowed in the first state: it ramps the load and the cavities' own controls"},
      {targets("{d: {pressure: 1}}"), "states[1].cavities.d",
       "not a declared cavity (did you mean 'c'? cavities: c, g, v)"},
      {kBase + "states: [{name: rest}, {name: up, cavities: {c: {pressure: 1}}}]\n",
       "states[1].cavities.c", "not a declared cavity (the deck has no cavities section)"},
      {targets("[c]"), "states[1].cavities", "expected a map of cavity name"},
      {targets("{c: 5}"), "states[1].cavities.c", "expected a map, got '5'"},
      {targets("{c: {volume: 1e-6}}"), "states[1].cavities.c.volume",
       "unknown key (did you mean 'pressure'? valid keys: pressure, added_volume)"},
      {targets("{c: {pressure: 1, added_volume: 1e-6}}"), "states[1].cavities.c",
       "give exactly one of pressure or added_volume"},
      {targets("{c: {}}"), "states[1].cavities.c", "give exactly one of pressure or added_volume"},
      {targets("{c: {pressure: high}}"), "states[1].cavities.c.pressure",
       "expected a number, got 'high'"},
      {targets("{c: {pressure: 1}, c: {pressure: 2}}"), "states[1].cavities.c", "duplicate key"},
      {targets("{g: {pressure: 1}}"), "states[1].cavities.g",
       "cavity 'g' is sealed_gas: only pneumatic and hydraulic cavities are actuated, so a "
       "state cannot set it"},
      {targets("{v: {added_volume: 1e-6}}"), "states[1].cavities.v",
       "cavity 'v' is sealed_volume: only pneumatic and hydraulic cavities are actuated"},
  });
}

TEST_F(DeckErrors, CavitiesAndStatesAgainstTime) {
  // A dynamic run's states are a schedule in time (docs/decks.md, "Dynamic runs with cavities
  // and cables"): each at a time on a time step, in order, within the run.
  const std::string dynamic = "time: {type: dynamic, dt: 0.1, end_time: 1}\n";
  const std::string two = cavity("group: c") + dynamic + "states:\n  - {name: rest}\n";
  auto second = [&](const std::string& fields) {
    return two + "  - {name: up, " + fields + ", cavities: {c: {pressure: 1}}}\n";
  };
  expect_errors({
      {second("steps: 3"), "states[1].steps", "not used when time.type is dynamic"},
      {two + "  - {name: up, cavities: {c: {pressure: 1}}}\n", "states[1].time",
       "required in a dynamic run after the first state"},
      {second("time: 0.25"), "states[1].time",
       "0.25 s is not on a time step (a multiple of time.dt = 0.1 s; the nearest are 0.2 and "
       "0.3)"},
      {second("time: -0.1"), "states[1].time", "must be >= 0, got -0.1"},
      {second("time: 1.5"), "states[1].time", "1.5 s is after time.end_time, 1 s"},
      {cavity("group: c") + dynamic + "states:\n  - {name: rest, time: 0.5}\n" +
           "  - {name: up, time: 0.3, cavities: {c: {pressure: 1}}}\n",
       "states[1].time", "0.3 s is before the previous state's time, 0.5 s (states[0])"},
      {cavity("group: c") + dynamic + "states:\n  - {name: rest, time: 1}\n" +
           "  - {name: up, time: 1, cavities: {c: {pressure: 1}}}\n",
       "states[1].time", "past time.end_time (1 s): give a later time.end_time"},
      {two + "  - {name: up, time: 0.3, cavities: {c: {pressure: 1}}}\n" +
           "  - {name: down, time: 0.3, cavities: {c: {pressure: 0}}}\n" +
           "  - {name: again, time: 0.4, cavities: {c: {pressure: 1}}}\n",
       "states[3].time",
       "0.4 s leaves its ramp no time step: states[2] is a step applied over the time step up "
       "to 0.4 s"},
      {cavity("group: c") + "states: [{name: rest, time: 0}]\n", "states[0].time",
       "only used when time.type is dynamic"},
      {kBase + "time: {steps: 3}\nstates: [{name: rest, steps: 3}]\n", "time.steps",
       "not used when states are given (the first state's steps replace it)"},
      {kBase + "time: {type: quasi_static, schedule: [0.5, 1]}\nstates: [{name: rest}]\n",
       "time.schedule", "not used when states are given"},
  });
}

// The control section (docs/decks.md, "control"): cavities "c" (hydraulic), "p" (pneumatic),
// "g" (sealed gas) and "v" (sealed volume), and a control section with the given effectors,
// actuators and further lines.
std::string control(const std::string& effectors, const std::string& actuators,
                    const std::string& more = "") {
  return kBase +
         "cavities:\n  - {group: c, kind: hydraulic}\n  - {group: p}\n"
         "  - {group: g, kind: sealed_gas}\n  - {group: v, kind: sealed_volume}\n"
         "control:\n  effectors: " +
         effectors + "\n  actuators: " + actuators + "\n" + more;
}
const std::string kTip = "[{name: tip, point: effector}]";
const std::string kActuator = "[{cavity: c}]";

// One effector "tip" with the given keys besides its name.
std::string effector(const std::string& fields) {
  return control("[{name: tip, " + fields + "}]", kActuator);
}
// One actuator of cavity "c" with the given keys besides its cavity.
std::string actuator(const std::string& fields) {
  return control(kTip, "[{cavity: c, " + fields + "}]");
}
// The effector "tip" and an actuator, with the given further lines of the control section.
std::string control_with(const std::string& more) { return control(kTip, kActuator, more); }
// The same with a boundary group "base", which a target set may move.
std::string control_moving(const std::string& more) {
  return control_with(more).insert(kBase.size(), "boundary: [{group: base}]\n");
}

TEST_F(DeckErrors, ControlKeysAndTypes) {
  expect_errors({
      {control_with("  stpes_per_target: 3\n"), "control.stpes_per_target",
       "unknown key (did you mean 'steps_per_target'?"},
      {control_with("  targets_from_stdin: true\n"), "control.targets_from_stdin",
       "not a deck key: the command line sets it (--targets -)"},
      {kBase + "control: [tip]\n", "control", "expected a map, got a list"},
      {kBase + "cavities: [{group: c}]\ncontrol: {actuators: [{cavity: c}]}\n", "control.effectors",
       "required key missing"},
      {kBase + "control: {effectors: [{name: tip, point: effector}]}\n", "control.actuators",
       "required key missing"},
      {control("{name: tip, point: effector}", kActuator), "control.effectors",
       "expected a list, got a map"},
      {control(kTip, "c"), "control.actuators", "expected a list, got 'c'"},
      {control("[]", kActuator), "control.effectors", "at least one effector is required"},
      {control(kTip, "[]"), "control.actuators", "at least one actuator is required"},
      {effector("point: effector, wieght: 2"), "control.effectors[0].wieght",
       "unknown key (did you mean 'weight'?"},
      {control("[{point: effector}]", kActuator), "control.effectors[0].name",
       "required key missing"},
      {control("[tip]", kActuator), "control.effectors[0]", "expected a map, got 'tip'"},
      {effector("point: effector, weight: heavy"), "control.effectors[0].weight",
       "expected a number, got 'heavy'"},
      {effector("position: [0, 1]"), "control.effectors[0].position",
       "expected a list of 3 numbers, got 2"},
      {effector("point: [effector]"), "control.effectors[0].point", "expected a name, got a list"},
      {effector("point: effector, directions: x"), "control.effectors[0].directions",
       "expected a list, got 'x'"},
      {effector("point: effector, directions: [x, w]"), "control.effectors[0].directions[1]",
       "unknown name 'w' (valid: x, y, z)"},
      {actuator("max_presure: 1"), "control.actuators[0].max_presure",
       "unknown key (did you mean 'max_pressure'?"},
      {actuator("max_pressure: high"), "control.actuators[0].max_pressure",
       "expected a number, got 'high'"},
      {actuator("min_volume_growth: \"0\""), "control.actuators[0].min_volume_growth",
       "expected a number, got the string \"0\""},
      {control_with("  steps_per_target: 2.5\n"), "control.steps_per_target",
       "expected an integer, got '2.5'"},
      {control_with("  regularization: small\n"), "control.regularization",
       "expected a number, got 'small'"},
      {control_with("  newton_finish: maybe\n"), "control.newton_finish",
       "expected true or false, got 'maybe'"},
      {control_with("  free_solve: fast\n"), "control.free_solve", "'fast'"},
      {control_moving("  targets: [{tip: [0, 0, 0], move: {bse: [0, 0, 1]}}]\n"),
       "control.targets[0].move.bse", "not a boundary group (did you mean 'base'?"},
      {control_moving("  targets: [{move: {base: [0, 0, 1]}}]\n"), "control.targets[0]",
       "a target set names at least one effector besides its move"},
      {control_moving("  targets: [{tip: [0, 0, 0], move: {base: [0, 0, 1]}}]\n  free_solve: "
                      "one_step\n"),
       "control.targets[0].move", "not supported with control.free_solve one_step"},
      {control("[{name: move, point: effector}]", kActuator), "control.effectors[0].name",
       "'move' is a target set's key"},
      {control_with("  check_every: 4\n"), "control.check_every", "needs check_equilibrium: true"},
      {control_with("  error_indicator: true\n"), "control.error_indicator", "needs reduced_model"},
      {control_with("  check_equilibrium: true\n  check_every: 0\n"), "control.check_every",
       "must be >= 1, got 0"},
      {control_with("  targets: {tip: [0, 0, 0]}\n"), "control.targets",
       "expected a list, got a map"},
      {control_with("  targets: [[0, 0, 0]]\n"), "control.targets[0]",
       "expected a map of effector name: [x, y, z]"},
      {control_with("  targets: [{tip: [0, 0]}]\n"), "control.targets[0].tip",
       "expected a list of 3 numbers, got 2"},
      {control_with("  targets: [{tip: [0, 0, 0], tip: [1, 1, 1]}]\n"), "control.targets[0].tip",
       "duplicate key"},
  });
}

TEST_F(DeckErrors, ControlEffectors) {
  expect_errors({
      {effector("point: effector, position: [0.09, 0, 0]"), "control.effectors[0]",
       "give exactly one of point (a point group with one node), position (a material point, "
       "in reference coordinates), obstacle (the contact force on it) or between (the contact "
       "force one surface exerts on another)"},
      {effector("point: effector, between: [a, b]"), "control.effectors[0]",
       "give exactly one of point"},
      {effector("point: effector, obstacle: ball"), "control.effectors[0]",
       "give exactly one of point"},
      {effector("obstacle: ball"), "control.effectors[0].obstacle",
       "the deck has no obstacles (a contact-force effector needs one)"},
      {effector("weight: 2"), "control.effectors[0]", "give exactly one of point"},
      {effector("point: \"\""), "control.effectors[0].point", "must not be empty"},
      {control("[{name: tip, point: a}, {name: tip, position: [0, 0, 0]}]", kActuator),
       "control.effectors[1].name", "duplicate effector name 'tip' (also in control.effectors[0])"},
      {effector("point: effector, directions: []"), "control.effectors[0].directions",
       "must name at least one of x, y, z"},
      {effector("point: effector, directions: [z, x, z]"), "control.effectors[0].directions[2]",
       "direction 'z' named twice"},
      {effector("point: effector, weight: 0"), "control.effectors[0].weight", "must be > 0, got 0"},
      {effector("point: effector, weight: -2"), "control.effectors[0].weight",
       "must be > 0, got -2"},
  });
}

TEST_F(DeckErrors, ControlActuators) {
  expect_errors({
      {control(kTip, "[{max_pressure: 1}]"), "control.actuators[0].cavity", "required key missing"},
      {control(kTip, "[{cavity: d}]"), "control.actuators[0].cavity",
       "not a declared cavity (did you mean 'c'? cavities: c, p, g, v)"},
      {kBase + "control: {effectors: " + kTip + ", actuators: [{cavity: c}]}\n",
       "control.actuators[0].cavity", "not a declared cavity (the deck has no cavities section)"},
      {control(kTip, "[{cavity: g}]"), "control.actuators[0].cavity",
       "cavity 'g' is sealed_gas: only pneumatic and hydraulic cavities are actuated, so "
       "control cannot drive it"},
      {control(kTip, "[{cavity: p}, {cavity: v}]"), "control.actuators[1].cavity",
       "cavity 'v' is sealed_volume: only pneumatic and hydraulic cavities are actuated"},
      {control(kTip, "[{cavity: c}, {cavity: p}, {cavity: c}]"), "control.actuators[2].cavity",
       "duplicate actuator cavity 'c' (also in control.actuators[0])"},
      {actuator("min_pressure: 3000, max_pressure: 2000"), "control.actuators[0].min_pressure",
       "is 3000 but max_pressure is 2000 (the lower bound must not exceed the upper one)"},
      {actuator("min_volume_growth: 2.0e-5, max_volume_growth: -1.0e-5"),
       "control.actuators[0].min_volume_growth",
       "is 2e-05 but max_volume_growth is -1e-05 (the lower bound must not exceed the upper "
       "one)"},
      {actuator("max_pressure_change: 0"), "control.actuators[0].max_pressure_change",
       "must be > 0, got 0"},
      {actuator("max_pressure_change: -500"), "control.actuators[0].max_pressure_change",
       "must be > 0, got -500"},
  });
}

TEST_F(DeckErrors, ControlTargetsAndSteps) {
  const std::string two = "[{name: tip, point: effector}, {name: base, position: [0, 0, 0]}]";
  expect_errors({
      {control_with("  targets: [{tpi: [0.09, 0, 0]}]\n"), "control.targets[0].tpi",
       "not an effector (did you mean 'tip'? effectors: tip)"},
      {control(two, kActuator,
               "  targets:\n    - {tip: [0, 0, 1]}\n    - {tip: [0, 0, 2], top: [0, 0, 3]}\n"),
       "control.targets[1].top", "not an effector (did you mean 'tip'? effectors: tip, base)"},
      {control_with("  targets: [{}]\n"), "control.targets[0]",
       "an empty target set (name at least one effector: tip)"},
      {control_with("  targets: [{tip: [0, 0, 1]}, {}]\n"), "control.targets[1]",
       "an empty target set"},
      {control_with("  targets: []\n"), "control.targets", "must hold at least one target set"},
      {control_with("  steps_per_target: 0\n"), "control.steps_per_target", "must be >= 1, got 0"},
      {control_with("  regularization: -1.0e-3\n"), "control.regularization",
       "must be >= 0, got -0.001"},
  });
}

// NaN and infinities (YAML .nan, .inf) anywhere in the section; an unset bound is already
// unbounded, so an infinite one is refused like any other.
TEST_F(DeckErrors, ControlNumbersAreFinite) {
  const std::string finite = "must be a finite number, got ";
  expect_errors({
      {effector("position: [0, .nan, 0]"), "control.effectors[0].position[1]", finite + "'.nan'"},
      {effector("point: effector, weight: .inf"), "control.effectors[0].weight", finite + "'.inf'"},
      {actuator("min_pressure: -.inf"), "control.actuators[0].min_pressure", finite + "'-.inf'"},
      {actuator("max_pressure: .inf"), "control.actuators[0].max_pressure", finite},
      {actuator("min_volume_growth: .NaN"), "control.actuators[0].min_volume_growth", finite},
      {actuator("max_volume_growth: .Inf"), "control.actuators[0].max_volume_growth", finite},
      {actuator("max_pressure_change: .inf"), "control.actuators[0].max_pressure_change", finite},
      {control_with("  targets: [{tip: [0, 0, 1]}, {tip: [.nan, 0, 0]}]\n"),
       "control.targets[1].tip[0]", finite},
      {control_with("  regularization: .nan\n"), "control.regularization", finite},
      {control_with("  steps_per_target: .inf\n"), "control.steps_per_target",
       "expected an integer, got '.inf'"},
  });
}

TEST_F(DeckErrors, ControlAgainstTime) {
  expect_errors({
      {kBase + "time: {type: dynamic, dt: 0.1, end_time: 1}\ncontrol: {effectors: " + kTip +
           ", actuators: " + kActuator + "}\n",
       "control", "control needs time.type static or quasi_static (time.type is dynamic)"},
  });
}

std::string error_of(const std::string& path) {
  try {
    parse_deck(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST_F(DeckErrors, DeckFileMissing) {
  const std::string path = (tmp.path() / "absent.yaml").string();
  EXPECT_EQ(error_of(path), path + ": deck file not found");
}

TEST_F(DeckErrors, InvalidYamlGivesTheLine) {
  // The flow list opened on line 3 is never closed: yaml-cpp stops at line 4.
  const std::string path = tmp.write("broken.yaml", kMesh + "materials:\n  - [1, 2\ntime: {}\n");
  const std::string message = error_of(path);
  EXPECT_EQ(message.rfind(path + ": line 4, column ", 0), 0u) << message;
  EXPECT_NE(message.find("invalid YAML: end of sequence flow not found"), std::string::npos)
      << message;
}

TEST_F(DeckErrors, ASecondYamlDocumentIsRefused) {
  // Without the check, the part after '---' would be ignored without a word.
  const std::string path = tmp.write("two.yaml", kMesh + kMaterials + "---\ntime: {steps: 3}\n");
  EXPECT_EQ(error_of(path),
            path + ": line 5: a second YAML document; a deck is one document (remove the '---')");
}

TEST_F(DeckErrors, NotAMap) {
  const std::string path = tmp.write("list.yaml", "- mesh\n- materials\n");
  EXPECT_EQ(error_of(path).rfind(path + ": (top level): expected a map of sections", 0), 0u);
  const std::string empty = tmp.write("empty.yaml", "# nothing\n");
  EXPECT_EQ(error_of(empty), empty + ": mesh: required key missing (the deck is empty)");
}

TEST_F(DeckErrors, ErrorsGiveTheLineOfTheKey) {
  const std::string path =
      tmp.write("lines.yaml", kMesh +
                                  "materials:\n  - group: body\n"
                                  "    model: neo_hookean\n    E: 1\n    nu: 0.7\n");
  EXPECT_EQ(
      error_of(path),
      path + ": materials[0].nu: must lie in (-1, 0.5] (0.5: incompressible), got 0.7 (line 6)");
}

// The obstacles and contact sections (docs/contact.md).
std::string obstacles(const std::string& entry, const std::string& contact = "{surfaces: [skin]}") {
  return kMesh + kMaterials + "boundary: [{group: base}]\nobstacles:\n  - " + entry +
         "\ncontact: " + contact + "\n";
}

TEST_F(DeckErrors, AContactForceEffectorNamesAnObstacleOfTheDeck) {
  const std::string deck =
      obstacles("{name: ball, type: sphere, center: [0, 0, -1], radius: 0.5}") +
      "cavities:\n  - {group: c}\ncontrol:\n  effectors: [{name: press, obstacle: bal}]\n"
      "  actuators: [{cavity: c}]\n";
  auto with = [&](const std::string& from, const std::string& to) {
    std::string d = deck;
    d.replace(d.find(from), from.size(), to);
    return d;
  };
  expect_errors({
      {deck, "control.effectors[0].obstacle",
       "no obstacle named 'bal' (did you mean 'ball'? obstacles: ball)"},
      {with("obstacle: bal", "obstacle: ball, surfaces: [skim]"),
       "control.effectors[0].surfaces[0]", "'skim' is not one of contact.surfaces (skin)"},
      {with("obstacle: bal", "position: [0, 0, 0], surfaces: [skin]"),
       "control.effectors[0].surfaces", "needs obstacle (a contact force)"},
  });
}

TEST_F(DeckErrors, AContactForceBetweenSurfacesNamesTwoSelfContactSurfaces) {
  const std::string deck = kMesh + kMaterials +
                           "boundary: [{group: base}]\ncontact: {surfaces: [skin, tip], self: "
                           "true}\ncavities:\n  - {group: c}\ncontrol:\n  effectors: [{name: "
                           "grip, between: [skin, tip]}]\n  actuators: [{cavity: c}]\n";
  auto with = [&](const std::string& from, const std::string& to) {
    std::string d = deck;
    d.replace(d.find(from), from.size(), to);
    return d;
  };
  expect_errors({
      {with("between: [skin, tip]", "between: [skin, tap]"), "control.effectors[0].between[1]",
       "'tap' is not one of contact.surfaces (skin, tip)"},
      {with("between: [skin, tip]", "between: [skin]"), "control.effectors[0].between",
       "names two surfaces, [A, B]: the force A exerts on B (1 given)"},
      {with("between: [skin, tip]", "between: [skin, skin]"), "control.effectors[0].between",
       "names 'skin' twice"},
      {with("self: true", "self: false"), "control.effectors[0].between", "needs contact.self"},
  });
}

TEST_F(DeckErrors, ContactForcesInTheQpNeedFrictionlessObstaclesAndNewton) {
  const std::string deck = kMesh + kMaterials +
                           "boundary: [{group: base}]\nobstacles:\n  - {name: ball, type: sphere, "
                           "radius: 1, center: [0, 0, -2]}\ncontact: {surfaces: [skin]}\n"
                           "cavities:\n  - {group: c}\ncontrol:\n  effectors: [{name: press, "
                           "obstacle: ball}]\n  actuators: [{cavity: c}]\n  contact_forces: qp\n";
  auto with = [&](const std::string& from, const std::string& to) {
    std::string d = deck;
    d.replace(d.find(from), from.size(), to);
    return d;
  };
  const std::string key = "control.contact_forces";
  expect_errors({
      {with("radius: 1,", "radius: 1, friction: 0.5,"), key,
       "qp takes normal forces only: obstacle 'ball' has friction"},
      {with("surfaces: [skin]}", "surfaces: [skin], self: true}"), key,
       "qp is not supported with contact.self"},
      {with("contact_forces: qp", "contact_forces: qp\n  free_solve: one_step"), key,
       "qp needs free_solve: newton"},
      {with("contact_forces: qp",
            "contact_forces: qp\n  targets: [{press: [0, 0, -1], move: "
            "{base: [0, 0, 1]}}]"),
       key, "qp is not supported with a target set's move"},
      {with("contact_forces: qp", "contact_forces: qp\n  reduced_model: r.h5"), key,
       "qp is not supported with control.reduced_model"},
      {with("contact_forces: qp", "contact_forces: qb"), key, "qb"},
  });
}

TEST_F(DeckErrors, ObstaclesAndContact) {
  const std::string floor = "{name: floor, type: plane}";
  expect_errors({
      {obstacles("{name: ball, type: sphere}"), "obstacles[0].radius",
       "type sphere needs `radius`"},
      {obstacles("{name: ball, type: sphere, radius: 0}"), "obstacles[0].radius", "must be > 0"},
      {obstacles("{name: floor, type: plane, normal: [0, 0, 0]}"), "obstacles[0].normal",
       "a direction needs a non-zero length"},
      {obstacles("{name: rod, type: cylinder, radius: 1, axis: [0, 0, 0]}"), "obstacles[0].axis",
       "a direction needs a non-zero length"},
      {obstacles("{name: cup, type: box, size: [1, 0, 1]}"), "obstacles[0].size",
       "every edge length must be > 0, got 0"},
      {obstacles("{name: cup, type: box}"), "obstacles[0].size", "type box needs `size`"},
      {obstacles("{name: cam, type: box, size: [1, 1, 1], friction: 0.3, turn: [0, 0, 30]}"),
       "obstacles[0].turn", "friction on a turning obstacle is not modelled"},
      {obstacles("{name: floor, type: plane, pivot: [0, 0, 1]}"), "obstacles[0].pivot",
       "only used by type surface"},
      {obstacles("{name: floor, type: plane, radius: 1}"), "obstacles[0].radius",
       "only used by type sphere, cylinder (this obstacle is plane)"},
      {obstacles("{name: ball, type: sphere, radius: 1, normal: [0, 0, 1]}"), "obstacles[0].normal",
       "only used by type plane (this obstacle is sphere)"},
      {obstacles("{name: floor, type: wall}"), "obstacles[0].type", "box"},
      {obstacles("{name: cup, type: surface}"), "obstacles[0].file", "type surface needs `file`"},
      {obstacles("{name: cup, type: surface, file: cup.stl, scale: 0}"), "obstacles[0].scale",
       "must be > 0"},
      {obstacles("{name: ball, type: sphere, radius: 1, file: cup.stl}"), "obstacles[0].file",
       "only used by type surface (this obstacle is sphere)"},
      {obstacles("{name: cup, type: surface, file: cup.stl}"), "obstacles[0].file",
       "cup.stl: cannot read the surface: no such file"},
      {obstacles(floor + "\n  - " + floor), "obstacles[1].name",
       "duplicate obstacle name 'floor' (also obstacles[0])"},
      {obstacles(floor, "{surfaces: []}"), "contact.surfaces",
       "at least one surface group is required"},
      {obstacles(floor, "{surfaces: [skin], distance: -1}"), "contact.distance",
       "must be > 0, got -1"},
      {obstacles(floor, "{surfaces: [skin], stiffness: 0}"), "contact.stiffness",
       "must be > 0, got 0"},
      {obstacles(floor, "{distance: 1}"), "contact.surfaces", "required key missing"},
      {kMesh + kMaterials + "boundary: [{group: base}]\nobstacles:\n  - " + floor + "\n", "contact",
       "required with obstacles"},
      {kMesh + kMaterials + "boundary: [{group: base}]\ncontact: {surfaces: [skin]}\n", "contact",
       "only used with obstacles or contact.self"},
      {kMesh + kMaterials + "boundary: [{group: base}]\ncontact: {surfaces: [skin], self: 1}\n",
       "contact.self", "expected true or false, got '1'"},
      {obstacles("{name: floor, type: plane, friction: -0.1}"), "obstacles[0].friction",
       "must be >= 0 (a Coulomb coefficient), got -0.1"},
      {obstacles(floor, "{surfaces: [skin], slip: 0}"), "contact.slip", "must be > 0, got 0"},
      {obstacles("{name: floor, type: plane, friction: 0.5}") +
           "output: {checkpoint: {every: 1}}\n",
       "obstacles[0].friction", "friction is not supported with output.checkpoint"},
      {kMesh + kMaterials +
           "boundary: [{group: base}]\nstates:\n  - {name: a, move: {base: [0, 0, 1]}}\n",
       "states[0].move", "not allowed in the first state"},
      {kMesh + kMaterials +
           "boundary: [{group: base}]\nstates:\n  - {name: a}\n  - {name: b, move: {bse: [0, "
           "0, 1]}}\n",
       "states[1].move.bse", "not a boundary group (did you mean 'base'?"},
      {kMesh + kMaterials +
           "boundary: [{group: base}]\nstates:\n  - {name: a}\n  - {name: b, move: {base: [0, "
           "1]}}\n",
       "states[1].move.base", "3"},
      {kMesh + kMaterials +
           "boundary: [{group: base}]\nstates:\n  - {name: a}\n  - {name: b, move: {base: [0, "
           "0, 1]}}\noutput: {checkpoint: {every: 1}}\n",
       "states[1].move", "not supported with output.checkpoint"},
      {kMesh + kMaterials +
           "boundary: [{group: base}]\ncontact: {surfaces: [skin], self: true, friction_between: "
           "[{surfaces: [skin, skn], friction: 0.2}]}\n",
       "contact.friction_between[0].surfaces[1]", "'skn' is not one of contact.surfaces"},
      {kMesh + kMaterials +
           "boundary: [{group: base}]\ncontact: {surfaces: [skin], self: true, friction_between: "
           "[{surfaces: [skin], friction: 0.2}]}\n",
       "contact.friction_between[0].surfaces", "needs two surface names"},
      {kMesh + kMaterials +
           "boundary: [{group: base}]\ncontact: {surfaces: [skin], self: true, friction_between: "
           "[{surfaces: [skin, skin], friction: -1}]}\n",
       "contact.friction_between[0].friction", "must be >= 0"},
      {obstacles(floor,
                 "{surfaces: [skin], friction_between: [{surfaces: [skin, skin], "
                 "friction: 0.2}]}"),
       "contact.friction_between", "only with contact.self: true"},
      {obstacles(floor, "{surfaces: [skin], friction: 0.5}"), "contact.friction",
       "touch each other only with contact.self: true"},
      {obstacles(floor, "{surfaces: [skin], friction: -1}"), "contact.friction",
       "must be >= 0 (a Coulomb coefficient), got -1"},
      {kMesh + kMaterials +
           "boundary: [{group: base}]\ncontact: {surfaces: [skin], self: true, friction: 0.2}\n"
           "output: {checkpoint: {every: 1}}\n",
       "contact.friction", "friction is not supported with output.checkpoint"},
  });
}

// The cables section and cable actuators: a cable "t" from the tip towards the base.
std::string cables(const std::string& entry, const std::string& actuators = "[{cavity: c}]") {
  return control(kTip, actuators) + "cables:\n  - " + entry + "\n";
}
const std::string kCable =
    "{name: t, points: [[0.08, 0, 0], [0.02, 0, 0]], pull_point: [-0.01, 0, 0]}";

TEST_F(DeckErrors, Cables) {
  expect_errors({
      {cables("{name: t, points: [[0.08, 0, 0]]}"), "cables[0].points",
       "a cable needs at least two points, or one point and a pull_point (got 1 points and no "
       "pull_point)"},
      {cables("{name: t, points: [[0.08, 0, 0], [0.08, 0, 0]]}"), "cables[0].points[1]",
       "coincides with the point before it"},
      {cables("{name: t, points: [[0.08, 0, 0]], pull_point: [0.08, 0, 0]}"),
       "cables[0].pull_point", "coincides with the point before it"},
      {cables("{name: t, points: [[0.08, 0, 0], [0, 0, 0]], force: -1}"), "cables[0].force",
       "must be >= 0 (a cable pulls, it cannot push), got -1"},
      {cables("{name: c, points: [[0.08, 0, 0], [0, 0, 0]]}"), "cables[0].name",
       "'c' is also a cavity's name"},
      {cables("{name: t, points: [[0.08, 0], [0, 0, 0]]}"), "cables[0].points[0]",
       "expected a list of 3 numbers, got 2"},
      {cables("{name: t, point: [[0.08, 0, 0], [0, 0, 0]]}"), "cables[0].point", "unknown key"},
      {cables(kCable, "[{cable: u}]"), "control.actuators[0].cable",
       "not a declared cable (did you mean 't'? cables: t)"},
      {cables(kCable, "[{cable: t, min_force: -1}]"), "control.actuators[0].min_force",
       "must be >= 0 (a cable pulls, it cannot push)"},
      {cables(kCable, "[{cable: t, max_pressure: 10}]"), "control.actuators[0].max_pressure",
       "unknown key"},
      {cables(kCable, "[{cable: t, min_pull: 0.01, max_pull: 0.005}]"),
       "control.actuators[0].min_pull", "is 0.01 but max_pull is 0.005"},
      {cables(kCable, "[{cable: t, cavity: c}]"), "control.actuators[0].cable",
       "give one of cavity and cable, not both"},
      {cables(kCable, "[{cable: t}, {cable: t}]"), "control.actuators[1].cable",
       "duplicate actuator cable 't'"},
  });
}

}  // namespace
}  // namespace hs
