// The sections `obstacles` (rigid bodies the soft body may touch, each a signed distance
// shape of contact/obstacle.hpp) and `contact` (which of the body's surfaces touch, and the
// barrier's parameters). docs/contact.md.
#pragma once

#include <yaml-cpp/yaml.h>

#include <vector>

#include "common/deck_reader.hpp"
#include "deck/config.hpp"

namespace hs {

// The list `node` of section `obstacles`: names unique, each shape's size and direction
// checked (a normal or axis of length 0, a radius or edge <= 0 are refused).
std::vector<ObstacleShape> parse_obstacles(const DeckReader& r, const YAML::Node& node,
                                           const Config& c);
// The map `node` of section `contact`; needs the obstacles read before.
ContactConfig parse_contact(const DeckReader& r, const YAML::Node& node, const Config& c);

}  // namespace hs
