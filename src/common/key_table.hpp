// A table of a map's keys, each declared once: its name, the docs' type, default and meaning,
// how its value is read into a struct S and printed back, and when it applies. One table
// drives the map's parsing (unknown, missing and misplaced keys, type and range checks), its
// printout and its table in the docs. The deck's sections (deck/deck_keys.hpp) and the
// material laws (materials/law_keys.hpp) declare their keys with it.
//
// C is what a key's uses and readers see beside the map read so far: the configuration read
// so far for a deck section, nothing for a law.
#pragma once

#include <yaml-cpp/yaml.h>

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "common/deck_reader.hpp"

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

// When a key applies; where it does not, giving it is an error with `reason` and the
// printout leaves it out. `holds` sees the map read so far (the keys above it in the table)
// and the context.
template <class S, class C>
struct BasicKeyUse {
  std::function<bool(const S&, const C&)> holds;
  std::function<std::string(const S&)> reason;  // e.g. "only used when time.type is dynamic"
  std::string doc;                              // the docs' prefix, e.g. "dynamic"
};

template <class S, class C>
struct BasicKey {
  std::string name;
  std::string type;           // docs: "integer ≥ 1", "name", "3 numbers", ...
  std::string default_value;  // docs: "1", "`static`", "none", "required"
  std::string meaning;        // docs
  // Reads the value at `node` (path `key`) into the struct; throws through r.fail.
  using Reader = std::function<void(const DeckReader& r, const YAML::Node& node,
                                    const std::string& key, S& s, const C& c)>;
  // Writes the value as the deck spells it (the printout).
  using Writer = std::function<void(YAML::Emitter& out, const S& s, const C& c)>;
  Reader read;
  Writer write;
  std::vector<BasicKeyUse<S, C>> uses;    // all must hold
  bool required = false;                  // where it applies
  std::function<bool(const S&)> printed;  // empty: always printed where it applies

  BasicKey only(BasicKeyUse<S, C> use) && {
    uses.push_back(std::move(use));
    return std::move(*this);
  }
  BasicKey needed() && {
    required = true;
    default_value = uses.empty() ? "required" : "required if " + uses.front().doc;
    return std::move(*this);
  }
  BasicKey printed_when(std::function<bool(const S&)> when) && {
    printed = std::move(when);
    return std::move(*this);
  }
  BasicKey defaults_to(std::string text) && {
    default_value = std::move(text);
    return std::move(*this);
  }
};

// Builders of the keys of context C for the common kinds of value; the default is the
// struct's own.
template <class C>
struct KeyBuilder {
  template <class S>
  static BasicKey<S, C> new_key(std::string name, std::string type, std::string default_value,
                                std::string meaning) {
    BasicKey<S, C> k;
    k.name = std::move(name);
    k.type = std::move(type);
    k.default_value = std::move(default_value);
    k.meaning = std::move(meaning);
    return k;
  }

  template <class S, class Int>
  static BasicKey<S, C> integer_key(std::string name, Int S::*member, Limit limit,
                                    std::string meaning) {
    auto k = new_key<S>(std::move(name), "integer " + limit.doc,
                        doc_number(static_cast<double>(S{}.*member)), std::move(meaning));
    k.read = [member, limit](const DeckReader& r, const YAML::Node& n, const std::string& key, S& s,
                             const C&) {
      s.*member = r.integer(n, key);
      if (const std::string problem = limit.problem(s.*member); !problem.empty())
        r.fail(key, n, problem);
    };
    k.write = [member](YAML::Emitter& out, const S& s, const C&) { out << s.*member; };
    return k;
  }

  template <class S>
  static BasicKey<S, C> number_key(std::string name, double S::*member, Limit limit,
                                   std::string meaning) {
    auto k = new_key<S>(std::move(name), limit.doc.empty() ? "number" : "number " + limit.doc,
                        doc_number(S{}.*member), std::move(meaning));
    k.read = [member, limit](const DeckReader& r, const YAML::Node& n, const std::string& key, S& s,
                             const C&) {
      s.*member = r.number(n, key);
      if (const std::string problem = limit.problem(s.*member); !problem.empty())
        r.fail(key, n, problem);
    };
    k.write = [member](YAML::Emitter& out, const S& s, const C&) {
      out << format_number(s.*member);
    };
    return k;
  }

  // A number the map may leave out (none: not set).
  template <class S>
  static BasicKey<S, C> optional_number_key(std::string name, std::optional<double> S::*member,
                                            std::string meaning) {
    auto k = new_key<S>(std::move(name), "number", "none", std::move(meaning));
    k.read = [member](const DeckReader& r, const YAML::Node& n, const std::string& key, S& s,
                      const C&) { s.*member = r.number(n, key); };
    k.write = [member](YAML::Emitter& out, const S& s, const C&) {
      out << format_number(*(s.*member));
    };
    k.printed = [member](const S& s) { return (s.*member).has_value(); };
    return k;
  }

  template <class S>
  static BasicKey<S, C> bool_key(std::string name, bool S::*member, std::string meaning) {
    auto k =
        new_key<S>(std::move(name), "bool", S{}.*member ? "true" : "false", std::move(meaning));
    k.read = [member](const DeckReader& r, const YAML::Node& n, const std::string& key, S& s,
                      const C&) { s.*member = r.boolean(n, key); };
    k.write = [member](YAML::Emitter& out, const S& s, const C&) { out << s.*member; };
    return k;
  }

  template <class S>
  static BasicKey<S, C> text_key(std::string name, std::string S::*member, std::string type,
                                 std::string meaning) {
    auto k = new_key<S>(std::move(name), std::move(type), "none", std::move(meaning));
    k.read = [member](const DeckReader& r, const YAML::Node& n, const std::string& key, S& s,
                      const C&) { s.*member = r.text(n, key); };
    k.write = [member](YAML::Emitter& out, const S& s, const C&) { out << s.*member; };
    return k;
  }

  // A key read and printed in its own way (maps, lists, optional values).
  template <class S>
  static BasicKey<S, C> custom_key(std::string name, std::string type, std::string default_value,
                                   std::string meaning, typename BasicKey<S, C>::Reader read,
                                   typename BasicKey<S, C>::Writer write) {
    auto k =
        new_key<S>(std::move(name), std::move(type), std::move(default_value), std::move(meaning));
    k.read = std::move(read);
    k.write = std::move(write);
    return k;
  }

  // A use whose reason does not depend on the map.
  template <class S>
  static BasicKeyUse<S, C> use_when(std::function<bool(const S&, const C&)> holds,
                                    std::string reason, std::string doc) {
    return {std::move(holds), [reason](const S&) { return reason; }, std::move(doc)};
  }
};

template <class S, class C>
std::vector<std::string> key_names(const std::vector<BasicKey<S, C>>& table) {
  std::vector<std::string> names;
  for (const auto& k : table) names.push_back(k.name);
  return names;
}

// The first use of `k` that does not hold, or null.
template <class S, class C>
const BasicKeyUse<S, C>* unmet_use(const BasicKey<S, C>& k, const S& s, const C& c) {
  for (const auto& use : k.uses)
    if (!use.holds(s, c)) return &use;
  return nullptr;
}

// The uses of the keys `node` gives, checked against the whole map and the context (read_keys
// checks each use again once the map is read; a caller whose context grows later checks
// again then: parse_deck once later sections are read, as time.steps is not used with
// states, which it reads after time).
template <class S, class C>
void check_uses(const DeckReader& r, const YAML::Node& node, const std::string& key,
                const std::vector<BasicKey<S, C>>& table, const S& s, const C& c) {
  for (const auto& k : table)
    if (const YAML::Node n = node[k.name])
      if (const BasicKeyUse<S, C>* unmet = unmet_use(k, s, c))
        r.fail(child_key(key, k.name), n, unmet->reason(s));
}

// Reads the key `k` of the map `node` (path `key`) into `s`, if the map gives it: a key given
// where it does not apply, a required one missing, a value of the wrong type or out of its
// limits are each an error naming the file, the key and the reason.
template <class S, class C>
void read_key(const DeckReader& r, const YAML::Node& node, const std::string& key,
              const BasicKey<S, C>& k, S& s, const C& c) {
  const YAML::Node n = node[k.name];
  const BasicKeyUse<S, C>* unmet = unmet_use(k, s, c);
  if (!n) {
    if (k.required && !unmet) r.fail(child_key(key, k.name), node, "required key missing");
    return;
  }
  if (unmet) r.fail(child_key(key, k.name), n, unmet->reason(s));
  k.read(r, n, child_key(key, k.name), s, c);
}

// Reads the map `node` (path `key`) into `s`, key by key in the table's order (read_key); a
// key not in the table is an error too.
template <class S, class C>
void read_keys(const DeckReader& r, const YAML::Node& node, const std::string& key,
               const std::vector<BasicKey<S, C>>& table, S& s, const C& c) {
  r.check_map(node, key, key_names(table));
  for (const auto& k : table) read_key(r, node, key, k, s, c);
  check_uses(r, node, key, table, s, c);  // uses that depend on keys below them
}

// The keys that apply (and are printed) as `key: value` pairs, in the table's order, into a
// map the caller has begun.
template <class S, class C>
void write_keys(YAML::Emitter& out, const std::vector<BasicKey<S, C>>& table, const S& s,
                const C& c) {
  for (const auto& k : table) {
    if (unmet_use(k, s, c) || (k.printed && !k.printed(s))) continue;
    out << YAML::Key << k.name << YAML::Value;
    k.write(out, s, c);
  }
}

// The docs' table of a map: | key | type | default | meaning |.
template <class S, class C>
std::string markdown_table(const std::vector<BasicKey<S, C>>& table) {
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

}  // namespace hs
