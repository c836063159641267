// Typed, validated access to the YAML tree of one deck. Every accessor takes the node and
// its dotted key path (e.g. "materials[1].nu") and throws InputError as
// "FILE: KEY: reason (line N)" when the node has the wrong type or an unknown key.
#pragma once

#include <yaml-cpp/yaml.h>

#include <array>
#include <map>
#include <string>
#include <vector>

namespace hs {

class DeckReader {
 public:
  // `override_of_key`: for each key set from the command line, the override text, so
  // that an error on that key says where the bad value came from.
  DeckReader(std::string file, std::map<std::string, std::string> override_of_key);

  const std::string& file() const { return file_; }

  [[noreturn]] void fail(const std::string& key, const YAML::Node& node,
                         const std::string& reason) const;
  [[noreturn]] void fail(const std::string& key, const std::string& reason) const;

  // Requires a map whose keys are all in `known` (a key may appear once).
  void check_map(const YAML::Node& node, const std::string& key,
                 const std::vector<std::string>& known) const;
  // Requires a list (any length).
  void check_list(const YAML::Node& node, const std::string& key) const;

  double number(const YAML::Node& node, const std::string& key) const;  // finite
  int integer(const YAML::Node& node, const std::string& key) const;
  bool boolean(const YAML::Node& node, const std::string& key) const;
  std::string text(const YAML::Node& node, const std::string& key) const;  // any scalar
  std::vector<double> numbers(const YAML::Node& node, const std::string& key) const;
  std::array<double, 3> vector3(const YAML::Node& node, const std::string& key) const;
  std::map<std::string, double> number_map(const YAML::Node& node, const std::string& key) const;

 private:
  // The override that set `key` or one of its parents; empty if none.
  std::string override_for(const std::string& key) const;

  std::string file_;
  std::map<std::string, std::string> override_of_key_;
};

// Checks shared by the parsers of each section; each throws through r.fail.

// The value of `map`'s key `name` (its path: child_key(key, name)), which must be there.
YAML::Node required(const DeckReader& r, const YAML::Node& map, const std::string& key,
                    const std::string& name);
// A name that must be one of `valid` (the message lists them).
std::string one_of(const DeckReader& r, const YAML::Node& node, const std::string& key,
                   const std::vector<std::string>& valid);
void require(bool condition, const DeckReader& r, const YAML::Node& node, const std::string& key,
             const std::string& reason);
// A key that only matters in some configurations must not be given in the others.
void forbid(const DeckReader& r, const YAML::Node& map, const std::string& key,
            const std::string& name, const std::string& reason);

bool contains(const std::vector<std::string>& names, const std::string& name);

// "a.b" + "c" -> "a.b.c"; the root has the empty path.
std::string child_key(const std::string& parent, const std::string& name);
// "materials" + 2 -> "materials[2]".
std::string item_key(const std::string& parent, size_t index);

// The entry of `candidates` closest to `word` (Levenshtein distance), for "did you mean"; a
// spelled-out name of a symbol key (youngs, poisson) gives the symbol (E, nu).
std::string nearest(const std::string& word, const std::vector<std::string>& candidates);

// The shortest text that reads back as exactly `value` (e.g. 0.3, 1e+06).
std::string format_number(double value);

// `text` with its control characters written out (\r, \t, \x1b, ...): a message that quotes a
// deck's bytes stays one line on a terminal and cannot move its cursor.
std::string printable(const std::string& text);

// "a, b, c".
std::string join(const std::vector<std::string>& words, const std::string& separator = ", ");

}  // namespace hs
