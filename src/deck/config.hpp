// The resolved configuration of one run: what a YAML deck says, defaults filled in.
// docs/decks.md documents every key; parse_deck() validates before any work is done.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "contact/obstacle.hpp"

namespace hs {

class MaterialLaw;
struct ExactSolutionType;  // verification/registry.hpp

struct MeshConfig {
  std::string file;  // .msh (gmsh 4.x) or .geo; resolved relative to the deck's folder
  int order = 1;     // 1: Tet4, 2: Tet10
  std::map<std::string, double> parameters;  // .geo only: numbers set before meshing (e.g. h)
  int refine = 0;                            // .geo only: uniform refinements after meshing
  // .geo only: run the source as it is, even when it runs commands, writes files or names
  // files outside its own and the deck's folders (docs/reliability.md).
  bool trust_geo = false;
  // The most tetrahedra the mesh may have (after refinement); a .geo is refused before
  // meshing when its sizes already promise more, a .msh when its header says more.
  int64_t max_elements = 20'000'000;
  std::string deck_dir;  // the deck's folder (not a key): a .geo may read files there
};

// A material: what the deck owns (group, density) and the law its model names, made by the
// registry of src/materials/ from the rest of its map (its name, parameters, stress).
// The element a material's body is solved with (docs/formulation.md, "Nearly incompressible
// bodies"): auto picks F-bar on P2 meshes at nu >= 0.49, the displacement element otherwise
// (deck/element_formulation.hpp). The deck's choice is printed as given; parse_deck resolves it
// into `element`, which the run reads (never `automatic`).
enum class ElementFormulation { automatic, displacement, fbar, nodal_pressure };
inline const std::vector<std::string> kElementFormulationNames = {"auto", "displacement", "fbar",
                                                                  "nodal_pressure"};

struct MaterialConfig {
  std::string group;                                               // volume physical group
  std::shared_ptr<const MaterialLaw> law;                          // materials/material.hpp
  double density = 0;                                              // kg/m^3
  ElementFormulation formulation = ElementFormulation::automatic;  // as the deck asks
  ElementFormulation element = ElementFormulation::displacement;   // what runs
  std::string formulation_reason;   // why it runs (printed beside the material)
  std::string formulation_warning;  // the expected error of a locking element, or empty
};

struct DirichletConfig {
  std::string group;  // any physical group; all its nodes are constrained
  std::array<bool, 3> components{true, true, true};  // which of x, y, z are prescribed
  std::array<double, 3> value{0, 0, 0};              // prescribed displacement at full load
  bool scaled = true;  // follows the load factor (false: applied at once)
  bool exact = false;  // values from the deck's exact solution at the
                       // current load factor (verification decks)
};

struct PressureConfig {
  std::string group;  // surface physical group
  double value = 0;   // Pa at full load; positive pushes against the outward normal
};

// A dead traction: force per reference area, of fixed direction, on a surface group.
struct TractionConfig {
  std::string group;                     // surface physical group
  std::array<double, 3> value{0, 0, 0};  // Pa at full load
};

// static: load increments to full load; quasi_static: a schedule of load factors (it may
// unload); dynamic: implicit time stepping with inertia.
enum class TimeType { static_, quasi_static, dynamic };
enum class Integrator { newmark, backward_euler };
inline const std::vector<std::string> kTimeTypeNames = {"static", "quasi_static", "dynamic"};
inline const std::vector<std::string> kIntegratorNames = {"newmark", "backward_euler"};
struct TimeConfig {
  TimeType type = TimeType::static_;
  int steps = 1;                 // static: load increments; quasi_static: schedule steps;
                                 // with states: the first state's steps
  std::vector<double> schedule;  // load factor per step (default linear ramp); steps = its size
  double dt = 0;                 // dynamic only
  double end_time = 0;           // dynamic only
  Integrator integrator = Integrator::newmark;  // dynamic only
  double newmark_beta = 0.25, newmark_gamma = 0.5;
  int max_cutbacks = 8;  // halvings of a failed load increment before giving up
};

// A starting set of PETSc options: a direct solve (MUMPS) or CG/GMRES with algebraic multigrid.
enum class SolverPreset { mumps, gamg };
inline const std::vector<std::string> kSolverPresetNames = {"mumps", "gamg"};
struct SolverConfig {
  SolverPreset preset = SolverPreset::mumps;
  std::map<std::string, std::string> petsc_options;  // any PETSc option, without the dash
};

// When a run writes checkpoint.h5 (docs/output.md): after `every` converged steps or
// `minutes` of wall time since the last one, whichever comes first (0: not by that measure).
struct CheckpointConfig {
  int every = 0;
  double minutes = 0;
};

struct OutputConfig {
  std::string folder;    // default: out/<deck name>, relative to the working directory
  int every = 1;         // write every n-th step (the last one always)
  bool progress = true;  // a line per converged step on standard error (solvers/progress.hpp)
  std::optional<CheckpointConfig> checkpoint;  // none: no checkpoints
};

// The deck's exact solution: its entry in the registry of src/verification/ (null for
// exact.type none) and its parameters, checked by parse_deck. The run builds the solution
// from them (make_exact_solution of deck/exact_section.hpp).
struct ExactConfig {
  const ExactSolutionType* type = nullptr;
  std::map<std::string, double> parameters;
};

// A choice the deck spells as a name: the names in the enum's order, and the conversions.
template <class Enum>
Enum enum_of(const std::vector<std::string>& names, const std::string& name) {
  return static_cast<Enum>(std::find(names.begin(), names.end(), name) - names.begin());
}
template <class Enum>
const std::string& name_of(const std::vector<std::string>& names, Enum value) {
  return names.at(static_cast<size_t>(value));
}

// How a hydraulic cavity's liquid weight reaches the wall nodes (docs/cavities.md).
// column: the paper's Section III; column_head: its columns with the pressure at each floor's
// and ceiling's depth; hydrostatic: that pressure on every wall, in closed form.
enum class WeightMethod { column, column_head, hydrostatic };
enum class WeightDevice { cpu, cuda };  // cuda: column only
// converged: weight recomputed at every Newton iterate; linearized: the paper's J_w = w / v_c,
// distribution frozen at the start of each step.
enum class WeightCoupling { converged, linearized };
inline const std::vector<std::string> kWeightMethodNames = {"column", "column_head", "hydrostatic"};
inline const std::vector<std::string> kWeightDeviceNames = {"cpu", "cuda"};
inline const std::vector<std::string> kWeightCouplingNames = {"converged", "linearized"};
struct FluidWeightConfig {
  WeightMethod method = WeightMethod::hydrostatic;
  int grid = 200;       // column methods: N x N columns
  int subdivision = 4;  // P2 walls: each Tri6 face as n x n flat triangles
  WeightDevice device = WeightDevice::cpu;
  WeightCoupling coupling = WeightCoupling::converged;
};

enum class CavityKind { pneumatic, hydraulic, sealed_gas, sealed_volume, pressure_limited };
inline const std::vector<std::string> kCavityKindNames = {"pneumatic", "hydraulic", "sealed_gas",
                                                          "sealed_volume", "pressure_limited"};
// Pneumatic and hydraulic cavities are driven (pressure or added volume); sealed ones are not.
inline bool is_actuated(CavityKind kind) {
  return kind == CavityKind::pneumatic || kind == CavityKind::hydraulic;
}

// A closed surface of the mesh (boundary faces of a surface group) that holds gas or liquid.
struct CavityConfig {
  std::string group;  // surface physical group; its name is the cavity's name
  CavityKind kind = CavityKind::pneumatic;
  // pneumatic / hydraulic control in the first state (ramped with the load factor): a gauge
  // pressure in Pa, or the volume added in m^3 (the pressure is then an unknown).
  double pressure = 0;
  std::optional<double> added_volume;
  double density = 0;              // hydraulic: liquid density, kg/m^3 (0: weightless liquid)
  FluidWeightConfig fluid_weight;  // hydraulic only
  // sealed_gas: p V = const with the absolute pressure; gauge pressure at the mesh's volume.
  double initial_pressure = 0;
  double atmospheric_pressure = 101325;
  // pressure_limited: a pump delivers added_volume through a relief valve that opens at
  // this gauge pressure (Pa).
  double max_pressure = 0;
};

// A cable (docs/control.md): a path of material points of the body the cable runs through
// (reference coordinates, each located in its tetrahedron), optionally ending at a fixed
// pull point in space (its motor); its tension pulls every point along the path.
struct CableConfig {
  std::string name;                           // unique among cables and cavities
  std::vector<std::array<double, 3>> points;  // at least one; two with no pull point
  std::optional<std::array<double, 3>> pull_point;
  double force = 0;  // N, tension at the end of the first state (ramped), >= 0
  // Coulomb friction coefficient where the cable turns (the capstan equation), >= 0; 0: none.
  double friction = 0;
};

// A later state of a run (after the first): the load stays at full, the named cavities'
// controls ramp from their current values to these in `steps` increments.
struct CavityTarget {
  std::optional<double> pressure;      // Pa
  std::optional<double> added_volume;  // m^3, relative to the volume at the end of the first state
};
struct StateConfig {
  std::string name;
  int steps = 1;  // static and quasi-static runs
  // Dynamic runs: the time (s) at which its values are reached (the first state's: 0 unless
  // given; docs/decks.md, "Dynamic runs with cavities and cables").
  std::optional<double> time;
  std::map<std::string, CavityTarget> cavities;  // by cavity name (its group)
  // By boundary group: a translation (m) added to its prescribed displacement over the state
  // (a palm that rises once the fingers hold what they grasp). Static and quasi-static runs.
  std::map<std::string, std::array<double, 3>> moves;
};

// Inclination of a face group (e.g. a hanging tip) reported for every state.
struct TipConfig {
  std::string group;  // surface group whose mean deformed normal is measured
};

// Inverse control (docs/control.md): end effectors, the actuators' bounds, the targets.
// The deck section `control` (docs/decks.md); parse_deck checks all of it but whether a
// `position` lies in the mesh (the solver locates it).
struct EffectorConfig {
  std::string name;   // unique; target sets name it
  std::string point;  // a point physical group with one node, or empty: `position` is used
  std::array<double, 3> position{0, 0, 0};  // a material point, in reference coordinates
  // Or an obstacle's name: the effector is then the contact force the body exerts on it (N),
  // and its targets are forces.
  std::string obstacle;
  // With `obstacle`: only the force of the contact nodes on these surface groups of
  // contact.surfaces (one finger of a gripper); empty: all of them.
  std::vector<std::string> surfaces;
  // Or two of contact.surfaces, with contact.self: the effector is then the contact force the
  // first exerts on the second (N), e.g. one finger's grasp on an object of the same mesh.
  std::vector<std::string> between;
  std::array<bool, 3> directions{true, true, true};  // which of x, y, z are controlled
  double weight = 1;                                 // > 0, on its squared error
};
// An actuator of the controller: a constraint it drives, named, with bounds in that
// constraint's own units: its multiplier (a cavity's gauge pressure in Pa, a cable's tension
// in N) and the change of its measure since the rest state (the end of the deck's states: a
// cavity's added volume in m^3, a cable's pull, its shortening, in m).
// A bound left at +-1e300 is no bound (the deck did not set it).
struct ActuatorConfig {
  std::string constraint;  // a pneumatic or hydraulic cavity's group or a cable's name; unique
  double min_multiplier = -1e300, max_multiplier = 1e300;          // min <= max
  double min_measure_change = -1e300, max_measure_change = 1e300;  // min <= max
  double max_multiplier_step = 1e300;  // largest change of the multiplier per control step, > 0
};
struct ControlTarget {
  std::string effector;                     // an effector's name
  std::array<double, 3> position{0, 0, 0};  // where the effector should be (m)
};
enum class FreeSolve { newton, one_step };
inline const std::vector<std::string> kFreeSolveNames = {"newton", "one_step"};
enum class ContactForces { free_step, qp };
inline const std::vector<std::string> kContactForcesNames = {"free_step", "qp"};
struct ControlConfig {
  std::vector<EffectorConfig> effectors;  // at least one
  std::vector<ActuatorConfig> actuators;  // at least one
  // One entry per target set, in order; a set names at least one effector, each at most
  // once, in the deck's order. Empty when the deck gives no targets.
  std::vector<std::vector<ControlTarget>> targets;
  // Per target set (as many as targets): the boundary groups it translates over its steps (a
  // set's `move`, as a state's), empty for none.
  std::vector<std::map<std::string, std::array<double, 3>>> moves;
  int steps_per_target = 10;     // control steps spent on each target set
  double regularization = 1e-3;  // relative weight of |d lambda|^2 against the effector error
  bool newton_finish = false;    // end every step with Newton at the new actuation
  // "newton": the free configuration converged by Newton at the held actuation; "one_step":
  // the paper's real-time step, one linearisation (one assembly, one factorization) for the
  // free motion and the compliance together.
  FreeSolve free_solve = FreeSolve::newton;
  // "free_step": contact with the obstacles is the barrier's, solved inside each free
  // configuration, the compliance including it; "qp": the obstacles' normal forces on the
  // contact nodes are unknowns of the QP beside the actuation, under complementarity.
  ContactForces contact_forces = ContactForces::free_step;
  int refactor_every = 1;  // one_step: factorize the tangent every N steps (1: every step)
  // one_step: the step's correction is refined with its own factorization while its free
  // step moves a targeted effector by more than this (m; 0: never, the paper's single step).
  double one_step_tolerance = 1e-5;
  // one_step: after each target set, also solve for the equilibrium at its actuation (on a
  // copy, outside the step times) and report its error: the prediction's real accuracy.
  bool check_equilibrium = false;
  int check_every = 1;  // with check_equilibrium: the first target set and every N-th after it
  // one_step: threads that factor the tangent in the background while the loop steps on
  // with the latest factorization, corrected by GMRES on the current tangent (0: in line).
  int factor_threads = 0;
  bool targets_from_stdin = false;  // `--targets -` on the command line (not a deck key)
  // A reduced-order model (hydrosoft reduce) that answers the control steps in place of the
  // full model (docs/reduced_models.md); "" for none. A path from the working directory.
  std::string reduced_model;
  // With a reduced model: each answer's error also estimated from the full model's residual at
  // the answer (solvers/reduced/error_indicator.hpp); off, the held-back samples' largest error.
  bool error_indicator = false;
};

// Contact of the body with rigid obstacles (docs/contact.md): which of its surfaces may touch,
// and the barrier's reach and stiffness (unset: from the mesh and the materials, at the run).
struct ContactConfig {
  std::vector<std::string> surfaces;  // surface groups of the body
  std::optional<double> distance;     // dhat (m): the gap at which the barrier starts
  std::optional<double> stiffness;    // kappa (Pa/m): the barrier's scale
  std::optional<double> slip;         // eps_v (m): friction's slip between stick and slide
  bool self = false;                  // the surfaces also touch each other (self-contact)
  bool edges = true;                  // with self: edges kept off edges as well
  double friction = 0;                // Coulomb coefficient between the surfaces (with self)
  // Coefficients for particular pairs of the surfaces (a surface with itself: the same name
  // twice), in place of `friction` there.
  struct FrictionBetween {
    std::array<std::string, 2> surfaces;
    double friction = 0;
  };
  std::vector<FrictionBetween> friction_between;
};

// `hydrosoft reduce DECK -o MODEL.h5` (the command line's, not deck keys): the training of a
// reduced-order model (docs/reduced_models.md).
enum class TrainingDesignKind { grid, halton };

struct TrainingConfig {
  std::string output;  // the model file
  TrainingDesignKind design = TrainingDesignKind::grid;
  int samples = 17;                 // grid: per actuator, over its [min, max] range; halton: in all
  double energy_tolerance = 1e-10;  // POD: the discarded fraction of the snapshots' energy
  int max_modes = 40;
  double ecsw_tolerance = 1e-6;  // ECSW: |C w - b| / |b| on the training snapshots
};

struct Config {
  std::string deck_path;  // as given on the command line
  std::string deck_name;  // file stem, e.g. lame_sphere
  MeshConfig mesh;
  std::vector<MaterialConfig> materials;
  std::vector<DirichletConfig> dirichlet;
  std::array<double, 3> gravity{0, 0, 0};
  std::vector<PressureConfig> pressures;
  std::vector<TractionConfig> tractions;
  TimeConfig time;
  SolverConfig solver;
  OutputConfig output;
  ExactConfig exact;
  std::vector<CavityConfig> cavities;
  std::vector<CableConfig> cables;
  // The run's states in order. Empty: one state "final" (load ramped over time.steps). The
  // first state always ramps the load (gravity, pressures, Dirichlet values, the cavities'
  // own controls) from 0 to 1; later states only move cavity controls.
  std::vector<StateConfig> states;
  std::optional<TipConfig> tip;
  std::optional<ControlConfig> control;
  std::optional<TrainingConfig> training;  // hydrosoft reduce (the command line)
  std::vector<ObstacleShape> obstacles;
  ContactConfig contact;
};

}  // namespace hs
