// The keys of a deck section, each declared once: its name, the docs' type, default and meaning,
// how its value is read into the section's struct and printed back, and when it applies. One
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
#include "deck/config.hpp"

namespace hs {

// A bound on a number beyond its type: the docs' words ("≥ 1") and the check's.
struct Limit {
  std::string doc;                             // e.g. "≥ 1", "in [1, 8192]"
  std::function<std::string(double)> problem;  // the message, or empty where x is fine
};
// `note` follows the bound in the message, e.g. "must be >= 1 (converged steps), got 0".
Limit at_least(double low, const std::string& note = "");  // "must be >= low, got x"
Limit above(double low, const std::string& note = "");     // "must be > low, got x"
Limit within(double low, double high);  // "must be >= low, got x" or "must be <= high, got x"
Limit any_number();                     // no bound
std::string doc_number(double value);   // the docs' spelling: 20000000, not 2e+07

// Values as the printout writes them: numbers in flow style by format_number (the shortest
// text that reads back exactly), axes as a list of x, y, z.
void write_numbers(YAML::Emitter& out, const double* values, size_t n);
void write_axes(YAML::Emitter& out, const std::array<bool, 3>& on);
// A list of x, y, z, non-empty and without repeats (a repeat: "`what` 'z' named twice").
std::array<bool, 3> read_axes(const DeckReader& r, const YAML::Node& n, const std::string& key,
                              const std::string& what);

// When a key applies; where it does not, giving it is an error with `reason` and the
// printout leaves it out. `holds` sees the section read so far (the keys above it in the
// table) and the configuration read so far (the sections parse_deck read before).
template <class S>
struct KeyUse {
  std::function<bool(const S&, const Config&)> holds;
  std::function<std::string(const S&)> reason;  // e.g. "only used when time.type is dynamic"
  std::string doc;                              // the docs' prefix, e.g. "dynamic"
};

template <class S>
struct DeckKey {
  std::string name;
  std::string type;           // docs: "integer ≥ 1", "name", "3 numbers", ...
  std::string default_value;  // docs: "1", "`static`", "none", "required"
  std::string meaning;        // docs
  // Reads the value at `node` (path `key`) into the section; throws through r.fail.
  using Reader = std::function<void(const DeckReader& r, const YAML::Node& node,
                                    const std::string& key, S& s, const Config& c)>;
  // Writes the value as the deck spells it (the printout).
  using Writer = std::function<void(YAML::Emitter& out, const S& s, const Config& c)>;
  Reader read;
  Writer write;
  std::vector<KeyUse<S>> uses;            // all must hold
  bool required = false;                  // where it applies
  std::function<bool(const S&)> printed;  // empty: always printed where it applies

  DeckKey only(KeyUse<S> use) && {
    uses.push_back(std::move(use));
    return std::move(*this);
  }
  DeckKey needed() && {
    required = true;
    default_value = uses.empty() ? "required" : "required if " + uses.front().doc;
    return std::move(*this);
  }
  DeckKey printed_when(std::function<bool(const S&)> when) && {
    printed = std::move(when);
    return std::move(*this);
  }
  DeckKey defaults_to(std::string text) && {
    default_value = std::move(text);
    return std::move(*this);
  }
};

template <class S>
using KeyTable = std::vector<DeckKey<S>>;

// Builders for the common kinds of value; the default is the struct's own (config.hpp).

template <class S>
DeckKey<S> new_key(std::string name, std::string type, std::string default_value,
                   std::string meaning) {
  DeckKey<S> k;
  k.name = std::move(name);
  k.type = std::move(type);
  k.default_value = std::move(default_value);
  k.meaning = std::move(meaning);
  return k;
}

template <class S, class Int>
DeckKey<S> integer_key(std::string name, Int S::*member, Limit limit, std::string meaning) {
  DeckKey<S> k = new_key<S>(std::move(name), "integer " + limit.doc,
                            doc_number(static_cast<double>(S{}.*member)), std::move(meaning));
  k.read = [member, limit](const DeckReader& r, const YAML::Node& n, const std::string& key, S& s,
                           const Config&) {
    s.*member = r.integer(n, key);
    if (const std::string problem = limit.problem(s.*member); !problem.empty())
      r.fail(key, n, problem);
  };
  k.write = [member](YAML::Emitter& out, const S& s, const Config&) { out << s.*member; };
  return k;
}

template <class S>
DeckKey<S> number_key(std::string name, double S::*member, Limit limit, std::string meaning) {
  DeckKey<S> k = new_key<S>(std::move(name), limit.doc.empty() ? "number" : "number " + limit.doc,
                            doc_number(S{}.*member), std::move(meaning));
  k.read = [member, limit](const DeckReader& r, const YAML::Node& n, const std::string& key, S& s,
                           const Config&) {
    s.*member = r.number(n, key);
    if (const std::string problem = limit.problem(s.*member); !problem.empty())
      r.fail(key, n, problem);
  };
  k.write = [member](YAML::Emitter& out, const S& s, const Config&) {
    out << format_number(s.*member);
  };
  return k;
}

// A number the deck may leave out (none: not set).
template <class S>
DeckKey<S> optional_number_key(std::string name, std::optional<double> S::*member,
                               std::string meaning) {
  DeckKey<S> k = new_key<S>(std::move(name), "number", "none", std::move(meaning));
  k.read = [member](const DeckReader& r, const YAML::Node& n, const std::string& key, S& s,
                    const Config&) { s.*member = r.number(n, key); };
  k.write = [member](YAML::Emitter& out, const S& s, const Config&) {
    out << format_number(*(s.*member));
  };
  k.printed = [member](const S& s) { return (s.*member).has_value(); };
  return k;
}

template <class S>
DeckKey<S> bool_key(std::string name, bool S::*member, std::string meaning) {
  DeckKey<S> k =
      new_key<S>(std::move(name), "bool", S{}.*member ? "true" : "false", std::move(meaning));
  k.read = [member](const DeckReader& r, const YAML::Node& n, const std::string& key, S& s,
                    const Config&) { s.*member = r.boolean(n, key); };
  k.write = [member](YAML::Emitter& out, const S& s, const Config&) { out << s.*member; };
  return k;
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

template <class S>
DeckKey<S> text_key(std::string name, std::string S::*member, std::string type,
                    std::string meaning) {
  DeckKey<S> k = new_key<S>(std::move(name), std::move(type), "none", std::move(meaning));
  k.read = [member](const DeckReader& r, const YAML::Node& n, const std::string& key, S& s,
                    const Config&) { s.*member = r.text(n, key); };
  k.write = [member](YAML::Emitter& out, const S& s, const Config&) { out << s.*member; };
  return k;
}

// A key the section reads and prints in its own way (maps, lists, optional values).
template <class S>
DeckKey<S> custom_key(std::string name, std::string type, std::string default_value,
                      std::string meaning, typename DeckKey<S>::Reader read,
                      typename DeckKey<S>::Writer write) {
  DeckKey<S> k =
      new_key<S>(std::move(name), std::move(type), std::move(default_value), std::move(meaning));
  k.read = std::move(read);
  k.write = std::move(write);
  return k;
}

// A use whose reason does not depend on the section.
template <class S>
KeyUse<S> use_when(std::function<bool(const S&, const Config&)> holds, std::string reason,
                   std::string doc) {
  return {std::move(holds), [reason](const S&) { return reason; }, std::move(doc)};
}

template <class S>
std::vector<std::string> key_names(const KeyTable<S>& table) {
  std::vector<std::string> names;
  for (const auto& k : table) names.push_back(k.name);
  return names;
}

// The first use of `k` that does not hold, or null.
template <class S>
const KeyUse<S>* unmet_use(const DeckKey<S>& k, const S& s, const Config& c) {
  for (const auto& use : k.uses)
    if (!use.holds(s, c)) return &use;
  return nullptr;
}

// The uses of the keys `node` gives, checked against the whole section and the configuration
// read so far (read_keys checks each use again once the section is read; parse_deck once
// later sections are: time.steps is not used with states, which it reads after time).
template <class S>
void check_uses(const DeckReader& r, const YAML::Node& node, const std::string& key,
                const KeyTable<S>& table, const S& s, const Config& c) {
  for (const auto& k : table)
    if (const YAML::Node n = node[k.name])
      if (const KeyUse<S>* unmet = unmet_use(k, s, c))
        r.fail(child_key(key, k.name), n, unmet->reason(s));
}

// Reads the key `k` of the map `node` (path `key`) into `s`, if the map gives it: a key given
// where it does not apply, a required one missing, a value of the wrong type or out of its
// limits are each an error naming the file, the key and the reason.
template <class S>
void read_key(const DeckReader& r, const YAML::Node& node, const std::string& key,
              const DeckKey<S>& k, S& s, const Config& c) {
  const YAML::Node n = node[k.name];
  const KeyUse<S>* unmet = unmet_use(k, s, c);
  if (!n) {
    if (k.required && !unmet) r.fail(child_key(key, k.name), node, "required key missing");
    return;
  }
  if (unmet) r.fail(child_key(key, k.name), n, unmet->reason(s));
  k.read(r, n, child_key(key, k.name), s, c);
}

// Reads the map `node` (path `key`) into `s`, key by key in the table's order (read_key); a
// key not in the table is an error too.
template <class S>
void read_keys(const DeckReader& r, const YAML::Node& node, const std::string& key,
               const KeyTable<S>& table, S& s, const Config& c) {
  r.check_map(node, key, key_names(table));
  for (const auto& k : table) read_key(r, node, key, k, s, c);
  check_uses(r, node, key, table, s, c);  // uses that depend on keys below them
}

// The keys that apply (and are printed) as `key: value` pairs, in the table's order, into a
// map the caller has begun.
template <class S>
void write_keys(YAML::Emitter& out, const KeyTable<S>& table, const S& s, const Config& c) {
  for (const auto& k : table) {
    if (unmet_use(k, s, c) || (k.printed && !k.printed(s))) continue;
    out << YAML::Key << k.name << YAML::Value;
    k.write(out, s, c);
  }
}

// The docs' table of a section: | key | type | default | meaning |.
template <class S>
std::string markdown_table(const KeyTable<S>& table) {
  std::string text = "| key | type | default | meaning |\n|---|---|---|---|\n";
  for (const auto& k : table) {
    std::string where;  // "dynamic, integrator `newmark`: "
    for (const auto& use : k.uses)
      if (!use.doc.empty()) where += (where.empty() ? "" : ", ") + use.doc;
    text += "| `" + k.name + "` | " + k.type + " | " + k.default_value + " | " +
            (where.empty() ? "" : where + ": ") + k.meaning + " |\n";
  }
  return text;
}

// The key tables that docs/decks.md shows, each by the name that marks it there
// (<!-- keys:NAME --> ... <!-- /keys -->).
struct DeckKeyTable {
  std::string name;
  std::string markdown;
};
std::vector<DeckKeyTable> deck_key_tables();

}  // namespace hs
