// Two `boundary` entries that prescribe the same component of the same node differently (a
// clamped group and a moved one that share an edge, a symmetry plane and a pulled face) have
// no solution together. Before, the later entry silently won on those nodes, and a load step
// that could not follow both halved its increment without end. Refused before any solve,
// naming both entries (docs/decks.md, "boundary"; docs/reliability.md).
#pragma once

#include <mpi.h>

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "deck/config.hpp"

namespace hs {

// The displacement of the deck's exact solution at reference point X and load factor s (for
// entries with `exact: true`); empty when the deck has none.
using ExactValue = std::function<std::array<double, 3>(const std::array<double, 3>& X, double s)>;

// Throws InputError (the same message on every rank) when two entries of config.dirichlet
// prescribe one component of one node differently: different values, one applied at once
// and the other ramped, or a value and an exact solution's that differ there. Collective over
// comm: each rank passes its nodes (coordinates x, 3 each; the first `owned` are its own, the
// others seen by another rank too) and, per group, the nodes of the group among them, all of
// them (a node on this rank is listed under every group it belongs to).
template <class Index>
void check_boundary_conflicts(const Config& config,
                              const std::map<std::string, std::vector<Index>>& groups,
                              const std::vector<double>& x, int64_t owned, const ExactValue& exact,
                              MPI_Comm comm);

}  // namespace hs
