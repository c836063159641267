// parse_cables: the cables of a soft robot (docs/decks.md, section `cables`): each a
// path of material points of the body, optionally ending at a fixed pull point, and its
// tension in the first state. Control drives them as actuators (docs/control.md).
#pragma once

#include <yaml-cpp/yaml.h>

#include <vector>

#include "common/deck_reader.hpp"
#include "deck/config.hpp"

namespace hs {

// The list `node` of section `cables`; names must differ from each other and from the
// cavities' (c.cavities, read before).
std::vector<CableConfig> parse_cables(const DeckReader& r, const YAML::Node& node, const Config& c);

}  // namespace hs
