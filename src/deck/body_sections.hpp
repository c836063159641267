// The deck sections `mesh`, `boundary` and `loads` (docs/decks.md): the body, what holds it
// and what loads it. Their keys are the tables of deck/section_keys.hpp.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>

#include "common/deck_reader.hpp"
#include "deck/config.hpp"

namespace hs {

// `deck_dir`: the deck's folder, where a relative mesh.file starts (empty: the working one).
MeshConfig parse_mesh(const DeckReader& r, const YAML::Node& node, const std::string& deck_dir,
                      const Config& c);
DirichletConfig parse_boundary(const DeckReader& r, const YAML::Node& node, const std::string& key,
                               const Config& c);
// Reads gravity and pressures into `c`.
void parse_loads(const DeckReader& r, const YAML::Node& node, Config& c);

}  // namespace hs
