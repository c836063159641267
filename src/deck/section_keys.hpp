// The key tables of the deck's sections (deck/deck_keys.hpp), each defined beside its
// section's parser; format_config prints with them and docs/decks.md's tables come from them.
#pragma once

#include "deck/deck_keys.hpp"

namespace hs {

const KeyTable<TimeConfig>& time_keys();  // run_sections.cpp
const KeyTable<TimeConfig>& newmark_keys();
const KeyTable<SolverConfig>& solver_keys();
const KeyTable<OutputConfig>& output_keys();
const KeyTable<CheckpointConfig>& checkpoint_keys();
const KeyTable<CavityConfig>& cavity_keys();  // cavity_sections.cpp
const KeyTable<FluidWeightConfig>& fluid_weight_keys();

}  // namespace hs
