// One run of hydrosoft on a resolved deck: mesh, distribution, problem, stepping, output.
// Static and quasi-static runs follow a schedule of load factors with automatic cutback;
// dynamic runs step in time with Newmark or backward Euler. Returns summary.json's object
// (complete on rank 0). `io`: where the interactive mode (control.targets_from_stdin) reads
// and answers its lines. `restart_folder` (--restart): continue from its checkpoint.h5
// (solvers/checkpoint.hpp) instead of from rest.
#pragma once

#include <mpi.h>

#include <nlohmann/json.hpp>
#include <string>

#include "deck/config.hpp"
#include "solvers/interactive_io.hpp"

namespace hs {

nlohmann::json run_simulation(const Config& config, MPI_Comm comm, InteractiveIo io = {},
                              const std::string& restart_folder = {});

}  // namespace hs
