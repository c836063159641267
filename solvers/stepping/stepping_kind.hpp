// The kind of stepping a deck runs, decided in one place (the stepper factory and the
// checkpoints' `kind` both ask here).
#pragma once

#include <string>

#include "deck/config.hpp"

namespace hs {

enum class SteppingKind {
  static_load,     // a schedule of load factors (static and quasi-static)
  dynamic,         // implicit time steps at full load
  states,          // the deck's states, with cavities, cables or a tip (bordered Newton)
  dynamic_states,  // time steps with cavities, cables or a tip: the states as a schedule in time
  control,         // its states, then its target sets
  reduce,          // a control deck's states, then the training of a reduced model
};

// A scene with cavities, cables, states, a tip or control runs its states (bordered Newton),
// in time steps when it is dynamic; any other its load schedule or its time steps (SNES).
SteppingKind stepping_kind_of(const Config& config);

// "static", "dynamic", "states", "dynamic_states" or "control": the name a checkpoint records.
std::string stepping_kind_name(SteppingKind kind);

// Whether the kind solves with constraints (ConstraintSet, BorderedNewton): no cavity code
// runs in a scene without them.
inline bool has_constraints(SteppingKind kind) {
  return kind == SteppingKind::states || kind == SteppingKind::dynamic_states ||
         kind == SteppingKind::control || kind == SteppingKind::reduce;
}

}  // namespace hs
