// The deck section `control` (docs/decks.md): inverse control of a soft robot, i.e. end
// effectors, the cavities that actuate them with their bounds, and the targets to reach.
#pragma once

#include <yaml-cpp/yaml.h>

#include "common/deck_reader.hpp"
#include "deck/config.hpp"

namespace hs {

// The map `node` of section `control`. Needs c.cavities and c.cables read already: its
// actuators are declared pneumatic or hydraulic cavities and cables.
ControlConfig parse_control(const DeckReader& r, const YAML::Node& node, const Config& c);

}  // namespace hs
