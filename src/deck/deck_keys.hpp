// The keys of a deck section, each declared once (common/key_table.hpp, with the configuration
// read so far as the context of its uses): its name, the docs' type, default and meaning, how
// its value is read into the section's struct and printed back, and when it applies. One
// table drives the section's parsing (unknown, missing and misplaced keys, type and range
// checks), its part of format_config (the printout and the restart fingerprint) and its table
// in docs/decks.md (deck_key_tables, tests/deck/test_deck_keys.cpp).
#pragma once

#include <yaml-cpp/yaml.h>

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "common/deck_reader.hpp"
#include "common/key_table.hpp"
#include "deck/config.hpp"

namespace hs {

// Values as the printout writes them: numbers in flow style by format_number (the shortest
// text that reads back exactly), axes as a list of x, y, z.
void write_numbers(YAML::Emitter& out, const double* values, size_t n);
void write_axes(YAML::Emitter& out, const std::array<bool, 3>& on);
// A list of x, y, z, non-empty and without repeats (a repeat: "`what` 'z' named twice").
std::array<bool, 3> read_axes(const DeckReader& r, const YAML::Node& n, const std::string& key,
                              const std::string& what);

// A section's keys see the configuration read so far (the sections parse_deck read before).
template <class S>
using KeyUse = BasicKeyUse<S, Config>;
template <class S>
using DeckKey = BasicKey<S, Config>;
template <class S>
using KeyTable = std::vector<DeckKey<S>>;
using DeckKeys = KeyBuilder<Config>;

// The builders of common/key_table.hpp for a section's keys.

template <class S>
DeckKey<S> new_key(std::string name, std::string type, std::string default_value,
                   std::string meaning) {
  return DeckKeys::new_key<S>(std::move(name), std::move(type), std::move(default_value),
                              std::move(meaning));
}

template <class S, class Int>
DeckKey<S> integer_key(std::string name, Int S::*member, Limit limit, std::string meaning) {
  return DeckKeys::integer_key<S>(std::move(name), member, std::move(limit), std::move(meaning));
}

template <class S>
DeckKey<S> number_key(std::string name, double S::*member, Limit limit, std::string meaning) {
  return DeckKeys::number_key<S>(std::move(name), member, std::move(limit), std::move(meaning));
}

template <class S>
DeckKey<S> optional_number_key(std::string name, std::optional<double> S::*member,
                               std::string meaning) {
  return DeckKeys::optional_number_key<S>(std::move(name), member, std::move(meaning));
}

template <class S>
DeckKey<S> bool_key(std::string name, bool S::*member, std::string meaning) {
  return DeckKeys::bool_key<S>(std::move(name), member, std::move(meaning));
}

template <class S>
DeckKey<S> text_key(std::string name, std::string S::*member, std::string type,
                    std::string meaning) {
  return DeckKeys::text_key<S>(std::move(name), member, std::move(type), std::move(meaning));
}

template <class S>
DeckKey<S> custom_key(std::string name, std::string type, std::string default_value,
                      std::string meaning, typename DeckKey<S>::Reader read,
                      typename DeckKey<S>::Writer write) {
  return DeckKeys::custom_key<S>(std::move(name), std::move(type), std::move(default_value),
                                 std::move(meaning), std::move(read), std::move(write));
}

template <class S>
KeyUse<S> use_when(std::function<bool(const S&, const Config&)> holds, std::string reason,
                   std::string doc) {
  return DeckKeys::use_when<S>(std::move(holds), std::move(reason), std::move(doc));
}

// A name of `names`, read into the enum (kTimeTypeNames and the like, config.hpp).
template <class S, class Enum>
DeckKey<S> enum_key(std::string name, Enum S::*member, const std::vector<std::string>& names,
                    std::string meaning) {
  DeckKey<S> k = new_key<S>(std::move(name), "name", "`" + name_of(names, S{}.*member) + "`",
                            std::move(meaning));
  k.read = [member, &names](const DeckReader& r, const YAML::Node& n, const std::string& key, S& s,
                            const Config&) {
    s.*member = enum_of<Enum>(names, one_of(r, n, key, names));
  };
  k.write = [member, &names](YAML::Emitter& out, const S& s, const Config&) {
    out << name_of(names, s.*member);
  };
  return k;
}

// A non-empty list of surface group names, printed as a flow list.
template <class S>
DeckKey<S> names_key(std::string name, std::vector<std::string> S::*member,
                     std::string default_value, std::string meaning) {
  DeckKey<S> k =
      new_key<S>(std::move(name), "list of names", std::move(default_value), std::move(meaning));
  k.read = [member](const DeckReader& r, const YAML::Node& n, const std::string& key, S& s,
                    const Config&) {
    r.check_list(n, key);
    require(n.size() > 0, r, n, key, "at least one surface group is required");
    for (size_t i = 0; i < n.size(); ++i) (s.*member).push_back(r.text(n[i], item_key(key, i)));
  };
  k.write = [member](YAML::Emitter& out, const S& s, const Config&) {
    out << YAML::Flow << s.*member;
  };
  return k;
}

// The key tables that docs/decks.md shows, each by the name that marks it there
// (<!-- keys:NAME --> ... <!-- /keys -->).
struct DeckKeyTable {
  std::string name;
  std::string markdown;
};
std::vector<DeckKeyTable> deck_key_tables();

}  // namespace hs
