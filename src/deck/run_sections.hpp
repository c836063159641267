// The deck sections `time`, `solver` and `output` (docs/decks.md): how a run steps, solves
// and writes. Their keys are the tables of deck/section_keys.hpp.
#pragma once

#include <yaml-cpp/yaml.h>

#include "common/deck_reader.hpp"
#include "deck/config.hpp"

namespace hs {

// Each reads its section's map `node` (checked against the configuration `c` read so far).
TimeConfig parse_time(const DeckReader& r, const YAML::Node& node, const Config& c);
SolverConfig parse_solver(const DeckReader& r, const YAML::Node& node, const Config& c);
OutputConfig parse_output(const DeckReader& r, const YAML::Node& node, const Config& c);

}  // namespace hs
