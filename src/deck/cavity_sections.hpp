// The deck sections `cavities` and `states` (docs/decks.md); their keys, and those of `tip`,
// are the tables of deck/section_keys.hpp.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "common/deck_reader.hpp"
#include "deck/config.hpp"

namespace hs {

// The list `node` of section `cavities`.
std::vector<CavityConfig> parse_cavities(const DeckReader& r, const YAML::Node& node,
                                         const Config& c);
// The list `node` of section `states`, whose targets name c.cavities (read before).
std::vector<StateConfig> parse_states(const DeckReader& r, const YAML::Node& node, const Config& c);

}  // namespace hs
