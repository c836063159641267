#include "common/deck_reader.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <set>
#include <utility>

#include "common/error.hpp"

namespace hs {
namespace {

// How a node looks, for "expected X, got Y".
std::string describe(const YAML::Node& node) {
  if (!node.IsDefined() || node.IsNull()) return "nothing";
  if (node.IsSequence()) return "a list";
  if (node.IsMap()) return "a map";
  if (node.Tag() == "!") return "the string \"" + node.Scalar() + "\"";
  return "'" + node.Scalar() + "'";
}

bool is_quoted(const YAML::Node& node) { return node.Tag() == "!"; }

size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t substitute = diagonal + (a[i - 1] == b[j - 1] ? 0 : 1);
      diagonal = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, substitute});
    }
  }
  return row[b.size()];
}

}  // namespace

std::string child_key(const std::string& parent, const std::string& name) {
  return parent.empty() ? name : parent + "." + name;
}

std::string item_key(const std::string& parent, size_t index) {
  return parent + "[" + std::to_string(index) + "]";
}

std::string nearest(const std::string& word, const std::vector<std::string>& candidates) {
  // Keys that are symbols (a law's E, nu) are far in spelling from the names people write for
  // them: those names first, where the symbol is a candidate.
  static const std::pair<const char*, const char*> kSpelledOut[] = {
      {"youngs", "E"},          {"young", "E"},           {"youngs_modulus", "E"},
      {"young_modulus", "E"},   {"elastic_modulus", "E"}, {"poisson", "nu"},
      {"poissons_ratio", "nu"}, {"poisson_ratio", "nu"},  {"rho", "density"},
      {"shear_modulus", "mu"},  {"bulk_modulus", "kappa"}};
  std::string lower;
  for (const char c : word) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (const auto& [name, key] : kSpelledOut)
    if (lower == name && std::find(candidates.begin(), candidates.end(), key) != candidates.end())
      return key;
  std::string best;
  size_t best_distance = std::string::npos;
  for (const auto& c : candidates) {
    const size_t d = edit_distance(word, c);
    if (d < best_distance) best = c, best_distance = d;
  }
  return best;
}

std::string format_number(double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

std::string printable(const std::string& text) {
  std::string out;
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u != 0x7f) {
      out += c;
    } else if (c == '\n' || c == '\r' || c == '\t') {
      out += c == '\n' ? "\\n" : c == '\r' ? "\\r" : "\\t";
    } else {
      static const char hex[] = "0123456789abcdef";
      out += std::string("\\x") + hex[u >> 4] + hex[u & 15];
    }
  }
  return out;
}

std::string join(const std::vector<std::string>& words, const std::string& separator) {
  std::string out;
  for (size_t i = 0; i < words.size(); ++i) out += (i ? separator : "") + words[i];
  return out;
}

bool contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

YAML::Node required(const DeckReader& r, const YAML::Node& map, const std::string& key,
                    const std::string& name) {
  const YAML::Node node = map[name];
  if (!node) r.fail(child_key(key, name), map, "required key missing");
  return node;
}

std::string one_of(const DeckReader& r, const YAML::Node& node, const std::string& key,
                   const std::vector<std::string>& valid) {
  const std::string name = r.text(node, key);
  if (!contains(valid, name))
    r.fail(key, node, "unknown name '" + name + "' (valid: " + join(valid) + ")");
  return name;
}

void require(bool condition, const DeckReader& r, const YAML::Node& node, const std::string& key,
             const std::string& reason) {
  if (!condition) r.fail(key, node, reason);
}

void forbid(const DeckReader& r, const YAML::Node& map, const std::string& key,
            const std::string& name, const std::string& reason) {
  if (map[name]) r.fail(child_key(key, name), map[name], reason);
}

DeckReader::DeckReader(std::string file, std::map<std::string, std::string> override_of_key)
    : file_(std::move(file)), override_of_key_(std::move(override_of_key)) {}

void DeckReader::fail(const std::string& key, const YAML::Node& node,
                      const std::string& reason) const {
  // Values from overrides carry the line of their own one-line document: no line then.
  std::string where;
  if (override_for(key).empty() && node.IsDefined() && node.Mark().line >= 0)
    where = " (line " + std::to_string(node.Mark().line + 1) + ")";
  fail(key, reason + where);
}

void DeckReader::fail(const std::string& key, const std::string& reason) const {
  const std::string from = override_for(key);
  throw InputError(printable(file_ + ": " + key + ": " + reason +
                             (from.empty() ? "" : " [from override '" + from + "']")));
}

std::string DeckReader::override_for(const std::string& key) const {
  for (const auto& [set_key, text] : override_of_key_) {
    const size_t n = set_key.size();
    const bool below =
        key.size() > n && key.compare(0, n, set_key) == 0 && (key[n] == '.' || key[n] == '[');
    if (key == set_key || below) return text;
  }
  return {};
}

void DeckReader::check_map(const YAML::Node& node, const std::string& key,
                           const std::vector<std::string>& known) const {
  if (!node.IsMap()) fail(key, node, "expected a map, got " + describe(node));
  std::set<std::string> seen;
  for (const auto& entry : node) {
    const std::string name = entry.first.Scalar();
    if (!seen.insert(name).second) fail(child_key(key, name), entry.first, "duplicate key");
    if (std::find(known.begin(), known.end(), name) == known.end())
      fail(child_key(key, name), entry.first,
           "unknown key (did you mean '" + nearest(name, known) + "'? valid keys: " + join(known) +
               ")");
  }
}

void DeckReader::check_list(const YAML::Node& node, const std::string& key) const {
  if (!node.IsSequence()) fail(key, node, "expected a list, got " + describe(node));
}

double DeckReader::number(const YAML::Node& node, const std::string& key) const {
  double value = 0;
  if (!node.IsScalar() || is_quoted(node) || !YAML::convert<double>::decode(node, value))
    fail(key, node, "expected a number, got " + describe(node));
  if (!std::isfinite(value)) fail(key, node, "must be a finite number, got " + describe(node));
  return value;
}

int DeckReader::integer(const YAML::Node& node, const std::string& key) const {
  int value = 0;
  if (!node.IsScalar() || is_quoted(node) || !YAML::convert<int>::decode(node, value))
    fail(key, node, "expected an integer, got " + describe(node));
  return value;
}

bool DeckReader::boolean(const YAML::Node& node, const std::string& key) const {
  bool value = false;
  if (!node.IsScalar() || is_quoted(node) || !YAML::convert<bool>::decode(node, value))
    fail(key, node, "expected true or false, got " + describe(node));
  return value;
}

std::string DeckReader::text(const YAML::Node& node, const std::string& key) const {
  if (!node.IsScalar()) fail(key, node, "expected a name, got " + describe(node));
  if (node.Scalar().empty()) fail(key, node, "must not be empty");
  return node.Scalar();
}

std::vector<double> DeckReader::numbers(const YAML::Node& node, const std::string& key) const {
  check_list(node, key);
  std::vector<double> values;
  for (size_t i = 0; i < node.size(); ++i) values.push_back(number(node[i], item_key(key, i)));
  return values;
}

std::array<double, 3> DeckReader::vector3(const YAML::Node& node, const std::string& key) const {
  check_list(node, key);
  if (node.size() != 3)
    fail(key, node, "expected a list of 3 numbers, got " + std::to_string(node.size()));
  const auto v = numbers(node, key);
  return {v[0], v[1], v[2]};
}

std::map<std::string, double> DeckReader::number_map(const YAML::Node& node,
                                                     const std::string& key) const {
  if (!node.IsMap()) fail(key, node, "expected a map of name: number, got " + describe(node));
  std::map<std::string, double> values;
  for (const auto& entry : node) {
    const std::string name = entry.first.Scalar();
    if (values.count(name)) fail(child_key(key, name), entry.first, "duplicate key");
    values[name] = number(entry.second, child_key(key, name));
  }
  return values;
}

}  // namespace hs
