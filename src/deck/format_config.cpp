// format_config: the resolved Config as a deck. The text is itself a valid deck that
// parse_deck reads back to the same Config (tests/deck), so a run can be repeated from
// its printed configuration. Keys that the configuration does not use (e.g. time.dt of a
// static run) are left out, as parse_deck would refuse them: the key tables of
// deck/section_keys.hpp say which, for parsing and printing alike.
#include <yaml-cpp/yaml.h>

#include "deck/deck.hpp"
#include "deck/section_keys.hpp"

namespace hs {

std::string format_config(const Config& c) {
  YAML::Emitter out;
  out << YAML::Comment("deck: " + c.deck_path);
  out << YAML::BeginMap;
  write_keys(out, deck_section_keys(), c, c);
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace hs
