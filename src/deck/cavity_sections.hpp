// The deck sections `cavities`, `states` and `tip` (docs/decks.md), parsed apart from the
// rest of the deck because they are checked against each other and against `time`.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>

#include "common/deck_reader.hpp"
#include "deck/config.hpp"

namespace hs {

// Reads root["cavities"], root["states"] and root["tip"] into `c`. Needs c.time parsed
// already: these sections need a static or quasi-static run, and `states` replaces
// time.steps and time.schedule (which must then be absent from root["time"]).
void parse_cavity_sections(const DeckReader& r, const YAML::Node& root, Config& c);

}  // namespace hs
