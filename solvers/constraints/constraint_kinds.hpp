// The registry of constraint kinds: which class a deck's cavity or cable becomes. A new kind
// is its class (solvers/constraints/<kind>.*) and one line in constraint_kinds.cpp;
// docs/architecture.md, "A constraint or actuator".
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "deck/config.hpp"
#include "solvers/constraints/constraint.hpp"

namespace hs {

// What every kind may need to be made: the scene and where its deck entry came from.
class ConstraintContext {
 public:
  ConstraintContext(Problem& problem, const Config& config) : problem(problem), config(config) {}
  Problem& problem;
  const Config& config;
  const std::string& deck_path() const { return config.deck_path; }
  // The rank that runs the fluid-weight module of the next liquid that weighs (round robin).
  int next_weighing_rank();

 private:
  int weighing_ = 0;
};

// The deck's constraints, in the deck's order: the cavities, then the cables. Collective;
// throws InputError for a bad one.
std::vector<std::unique_ptr<Constraint>> make_constraints(const Config& config, Problem& problem);

// summary.json's lists of constraints, each reported even when empty.
const std::vector<std::string>& constraint_families();

}  // namespace hs
