// Fields of a distributed run gathered on rank 0 in mesh numbering, for tests and checks on
// small meshes (the writer gathers nothing: output.hpp); no other rank returns anything.
#pragma once

#include <petscvec.h>

#include <vector>

#include "solvers/problem.hpp"

namespace hs {

// Owned-node values of a block-3 vector in mesh (old) numbering, gathered on rank 0.
std::vector<double> gather_nodal(const Problem& problem, Vec v);

}  // namespace hs
