// parse_cable_section: the cables of a soft robot (docs/decks.md, section `cables`): each a
// path of material points of the body, optionally ending at a fixed pull point, and its
// tension in the first state. Control drives them as actuators (docs/control.md).
#pragma once

#include <yaml-cpp/yaml.h>

#include "common/deck_reader.hpp"
#include "deck/config.hpp"

namespace hs {

// Fills c.cables; names must differ from each other and from the cavities' (after
// parse_cavity_sections). Dynamic runs have no cables.
void parse_cable_section(const DeckReader& r, const YAML::Node& root, Config& c);

}  // namespace hs
