// A law's deck keys are declared as a section's are (deck/deck_keys.hpp): one table over the
// law's parameters, each key once with its type, limits, default and meaning. The registry
// (registry.hpp) reads a law's map, prints it and writes its rows of docs/decks.md from it.
#pragma once

#include "deck/deck_keys.hpp"

namespace hs {

// A law's keys depend on no other section of the deck: its tables are read and printed
// against an empty configuration.
const Config& no_sections();

// The keys of `table` that the map `node` (path `key`) gives, read into `s` (the registry has
// already refused unknown keys and those of other laws).
template <class S>
void read_law_keys(const DeckReader& r, const YAML::Node& node, const std::string& key,
                   const KeyTable<S>& table, S& s) {
  for (const auto& k : table) read_key(r, node, key, k, s, no_sections());
}

template <class S>
void write_law_keys(YAML::Emitter& out, const KeyTable<S>& table, const S& s) {
  write_keys(out, table, s, no_sections());
}

}  // namespace hs
