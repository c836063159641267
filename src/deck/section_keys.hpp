// The key tables of the deck's sections (deck/deck_keys.hpp), each defined beside its
// section's parser; format_config prints with them and docs/decks.md's tables come from them.
#pragma once

#include "deck/deck_keys.hpp"

namespace hs {

// The deck's top-level map: its sections, in the printout's order (deck_sections.cpp).
const KeyTable<Config>& deck_section_keys();

const KeyTable<MaterialConfig>&
material_keys();  // deck_sections.cpp; a law's own keys: materials/registry.hpp
const KeyTable<MeshConfig>& mesh_keys();  // body_sections.cpp
const KeyTable<DirichletConfig>& boundary_keys();
const KeyTable<Config>& loads_keys();  // gravity, pressures and tractions
const KeyTable<PressureConfig>& pressure_keys();
const KeyTable<TractionConfig>& traction_keys();
const KeyTable<TimeConfig>& time_keys();  // run_sections.cpp
const KeyTable<TimeConfig>& newmark_keys();
const KeyTable<SolverConfig>& solver_keys();
const KeyTable<OutputConfig>& output_keys();
const KeyTable<CheckpointConfig>& checkpoint_keys();
const KeyTable<CavityConfig>& cavity_keys();  // cavity_sections.cpp
const KeyTable<FluidWeightConfig>& fluid_weight_keys();
const KeyTable<StateConfig>& state_keys();
const KeyTable<CavityTarget>& target_keys();  // a later state's target for a cavity
const KeyTable<TipConfig>& tip_keys();
const KeyTable<CableConfig>& cable_keys();      // cable_section.cpp
const KeyTable<ControlConfig>& control_keys();  // control_section.cpp
const KeyTable<EffectorConfig>& effector_keys();
const KeyTable<ActuatorConfig>& cavity_actuator_keys();
const KeyTable<ActuatorConfig>& cable_actuator_keys();
const KeyTable<ExactConfig>& exact_keys();       // exact_section.cpp
const KeyTable<ObstacleShape>& obstacle_keys();  // contact_section.cpp
const KeyTable<ContactConfig>& contact_keys();

}  // namespace hs
