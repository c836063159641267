// The deck's exact solution checked on the mesh before any work: a reference that is not a
// finite number there (parameters that overflow the closed form or divide by zero) is an
// input error naming `exact.parameters`, not a run whose summary cannot be written.
#pragma once

#include <mpi.h>

#include <vector>

#include "deck/config.hpp"
#include "verification/exact_solution.hpp"

namespace hs {

// Collective on comm: every rank checks its nodes x (3 numbers a node) and all throw the same
// InputError "DECK: exact.parameters: ..." when any rank finds a value that is not finite.
void check_reference_finite(const Config& config, const ExactSolution& exact,
                            const std::vector<double>& x, MPI_Comm comm);

}  // namespace hs
