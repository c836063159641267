// What a run prints when it ends: a few lines for people (steps, time, where the results are,
// and the run's own figures as a small table); summary.json in the output folder has it all.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace hs {

// From the run's summary (solvers/run_output.cpp writes its keys, docs/output.md lists them):
// "# hydrosoft: done: ..." and where the files are, then by kind of run the states (tip
// angle, each cavity's pressure, volume and added volume), the targets (target, reached,
// error, actuation), or the verification figures.
std::string run_report(const nlohmann::json& summary);

}  // namespace hs
