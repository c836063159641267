// The plan of a deck's states (docs/decks.md, "states"): the first ramps the load factor from 0
// to 1 with the cavities at their own controls; each later state ramps the cavity controls it
// names from their current values to its targets, and moves the boundary groups it names by
// their translations. A deck without states has one, "final".
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "deck/config.hpp"
#include "solvers/constraints/constraint_set.hpp"
#include "solvers/problem.hpp"
#include "solvers/stepping/boundary_moves.hpp"

namespace hs {

// One state: its increments' end points tau (fractions of the state) and what tau sets.
struct StatePlan {
  std::string name;
  std::vector<double> taus;
  bool first = false;
  // The constraints it names (a later state's cavities): the control to ramp (from -> to);
  // those it does not name keep theirs.
  struct Ramp {
    std::string constraint;
    Constraint::Control control = Constraint::Control::multiplier;
    double from = 0, to = 0;
  };
  std::vector<Ramp> ramps;
  BoundaryMoves moves;  // the boundary groups it moves (a later state's `move`)

  double load_factor(double tau) const { return first ? tau : 1.0; }
  // Starts the state: fixes its ramps' start values from the constraints' current state and
  // sets their controls. Throws InputError (naming the deck, the state and the cavity) for an
  // added volume that would leave a cavity no volume.
  void begin(ConstraintSet& constraints, const std::string& deck_path);
  // Sets the constraints' targets (and the prescribed multipliers) at tau.
  void set_targets(ConstraintSet& constraints, double tau) const;
  // Why a ramp may have no equilibrium ahead (a pressure past its peak), for a failed step.
  std::string failure_note(const ConstraintSet& constraints) const;
  // The ramps for a checkpoint, one entry per constraint, and the same put back.
  nlohmann::json ramps_json(const ConstraintSet& constraints) const;
  void resume_ramps(const nlohmann::json& ramps, const ConstraintSet& constraints);

 private:
  // Its ramp of constraint c, or nullptr.
  const Ramp* ramp_of(const Constraint& c) const;
};

std::vector<StatePlan> plan_states(const Config& config);

}  // namespace hs
