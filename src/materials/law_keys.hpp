// A law's deck keys are declared as a section's are (common/key_table.hpp): one table over the
// law's parameters, each key once with its type, limits, default and meaning. The registry
// (registry.hpp) reads a law's map, prints it and writes its rows of docs/decks.md from it.
#pragma once

#include "common/key_table.hpp"

namespace hs {

// A law's keys depend on no other part of the deck: their uses and readers see nothing.
struct NoSections {};
template <class S>
using LawKey = BasicKey<S, NoSections>;
template <class S>
using LawKeyTable = std::vector<LawKey<S>>;
using LawKeys = KeyBuilder<NoSections>;

// The keys of `table` that the map `node` (path `key`) gives, read into `s` (the registry has
// already refused unknown keys and those of other laws).
template <class S>
void read_law_keys(const DeckReader& r, const YAML::Node& node, const std::string& key,
                   const LawKeyTable<S>& table, S& s) {
  for (const auto& k : table) read_key(r, node, key, k, s, NoSections{});
}

template <class S>
void write_law_keys(YAML::Emitter& out, const LawKeyTable<S>& table, const S& s) {
  write_keys(out, table, s, NoSections{});
}

}  // namespace hs
