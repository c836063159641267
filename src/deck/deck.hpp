// Reading, validating and printing YAML input decks (docs/decks.md lists every key).
#pragma once

#include <string>
#include <vector>

#include "deck/config.hpp"
#include "mesh/mesh.hpp"

namespace hs {

// Parses and validates a deck. `overrides` are "dotted.key=value" strings from the
// command line (e.g. "mesh.order=2", "mesh.parameters.h=0.05") applied before validation.
// Throws InputError naming the file, the key and the reason: unknown keys, wrong types,
// missing required keys, non-physical values (E <= 0, nu outside (-1, 0.5], density < 0, ...).
Config parse_deck(const std::string& path, const std::vector<std::string>& overrides = {});

// Throws InputError if a group named by the deck is missing from the mesh or has no
// nodes, or a material group is not a volume, a pressure, cavity or tip group not a surface,
// or an effector's point group has more than one node.
void check_groups(const Config& config, const MeshGroups& mesh);

// The resolved configuration, defaults included, as YAML (printed at start).
std::string format_config(const Config& config);

}  // namespace hs
