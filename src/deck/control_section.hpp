// The deck section `control` (docs/decks.md): inverse control of a soft robot, i.e. end
// effectors, the cavities that actuate them with their bounds, and the targets to reach.
#pragma once

#include <yaml-cpp/yaml.h>

#include "common/deck_reader.hpp"
#include "deck/config.hpp"

namespace hs {

// Reads root["control"] into c.control (left empty without the section). Needs c.time and
// c.cavities parsed already: control needs a static or quasi-static run, and its actuators
// are declared pneumatic or hydraulic cavities.
void parse_control_section(const DeckReader& r, const YAML::Node& root, Config& c);

}  // namespace hs
