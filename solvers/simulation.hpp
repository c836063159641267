// One run of hydrosoft on a resolved deck: mesh, distribution, problem, stepping, output.
// Static and quasi-static runs follow a schedule of load factors with automatic cutback;
// dynamic runs step in time with Newmark or backward Euler. Returns summary.json's object
// (complete on rank 0).
#pragma once

#include <mpi.h>

#include <nlohmann/json.hpp>

#include "deck/config.hpp"

namespace hs {

nlohmann::json run_simulation(const Config& config, MPI_Comm comm);

}  // namespace hs
