// The deck sections `cavities` and `states` (docs/decks.md); their keys, and those of `tip`,
// are the tables of deck/section_keys.hpp.
#pragma once

#include <yaml-cpp/yaml.h>

#include <array>
#include <cstdint>
#include <map>
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

// A map of boundary group: translation (m), a later state's `move` or a control target
// set's: each a group of c.dirichlet (read before) without exact values.
std::map<std::string, std::array<double, 3>> parse_moves(const DeckReader& r,
                                                         const YAML::Node& node,
                                                         const std::string& key, const Config& c);

// A dynamic run's schedule of states: the time step at which each state's values are reached,
// m_k = time_k / dt, except where a state's time equals the one before it (a step): then its
// values are applied over the time step after that, m_k = m_(k-1) + 1. m_0 = 0 (the first
// state at time 0) applies the first state's values from t = 0 itself. Without states, the
// one implicit state is at time 0. The times are those parse_states checked.
std::vector<int64_t> state_time_steps(const std::vector<StateConfig>& states, double dt);

}  // namespace hs
