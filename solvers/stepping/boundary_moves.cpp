#include "solvers/stepping/boundary_moves.hpp"

namespace hs {

BoundaryMoves::BoundaryMoves(const std::map<std::string, std::array<double, 3>>& by) {
  for (const auto& [group, translation] : by) moves_.push_back({group, translation, {0, 0, 0}});
}

void BoundaryMoves::begin(const Problem& problem) {
  for (Move& m : moves_) m.from = problem.boundary_moved(m.group);
}

void BoundaryMoves::set(Problem& problem, double tau) const {
  for (const Move& m : moves_) {
    std::array<double, 3> at;
    for (int d = 0; d < 3; ++d) at[d] = m.from[d] + tau * m.by[d];
    problem.move_boundary(m.group, at);
  }
}

bool BoundaryMoves::one_translation(double tau0, double tau1, std::array<double, 3>& by) const {
  if (moves_.size() != 1) return false;
  for (int d = 0; d < 3; ++d) by[d] = (tau1 - tau0) * moves_[0].by[d];
  return true;
}

}  // namespace hs
