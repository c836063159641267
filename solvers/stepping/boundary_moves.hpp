// Boundary groups translated over a stretch of steps: a later state's `move` (docs/decks.md,
// "states") and a control target set's. Each group goes from the translation it has when the
// stretch begins by the deck's, ramped with tau from 0 to 1, on the components the group
// prescribes (DofMap::set_move); later stretches keep it.
#pragma once

#include <array>
#include <map>
#include <string>
#include <vector>

#include "solvers/problem.hpp"

namespace hs {

class BoundaryMoves {
 public:
  BoundaryMoves() = default;
  explicit BoundaryMoves(const std::map<std::string, std::array<double, 3>>& by);

  bool empty() const { return moves_.empty(); }
  // Starts the stretch from the groups' present translations.
  void begin(const Problem& problem);
  // The groups' translations at tau.
  void set(Problem& problem, double tau) const;
  // With one group: its translation from tau0 to tau1 (true); else false.
  bool one_translation(double tau0, double tau1, std::array<double, 3>& by) const;

 private:
  struct Move {
    std::string group;
    std::array<double, 3> by{0, 0, 0}, from{0, 0, 0};
  };
  std::vector<Move> moves_;
};

}  // namespace hs
