// Which rigid motions a static body's Dirichlet conditions leave free. A rigid motion is
// u(X) = t + w x (X - c); it is held when some constrained component sees it: the six modes
// restricted to the constrained components are independent, i.e. their Gram matrix
// G = sum over constrained (node, component) of r r^T, r_j = mode j's component there, has
// full rank. A free mode makes the tangent of a static run singular (every step fails), so
// it is refused before any work with the motion named. docs/decks.md, "boundary".
#pragma once

#include <mpi.h>

#include <array>
#include <map>
#include <string>
#include <vector>

#include "deck/config.hpp"

namespace hs {

// The motions left free, in words ("translation along z", "rotation about an axis along
// (0, 0.71, 0.71)"); empty when the conditions hold all six. Collective over comm: each rank
// passes its nodes (coordinates x, 3 each) and node groups; nodes seen by several ranks count
// more than once, which leaves the rank of G unchanged.
template <class Index>
std::vector<std::string> free_rigid_motions(const std::vector<DirichletConfig>& conditions,
                                            const std::map<std::string, std::vector<Index>>& groups,
                                            const std::vector<double>& x, MPI_Comm comm);

// Throws InputError naming the deck's `boundary` and the free motions, for a static or
// quasi-static deck whose conditions leave some free (a dynamic body may move rigidly).
template <class Index>
void check_rigid_motions_held(const Config& config,
                              const std::map<std::string, std::vector<Index>>& groups,
                              const std::vector<double>& x, MPI_Comm comm);

}  // namespace hs
