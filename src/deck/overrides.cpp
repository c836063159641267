#include "deck/overrides.hpp"

#include <cctype>

#include "common/deck_reader.hpp"
#include "common/error.hpp"

namespace hs {
namespace {

// One step of a key path: a map key, or a list index (name empty).
struct Step {
  std::string name;
  size_t index = 0;
};

bool is_name_char(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
}

// "materials[0].E" -> {materials}, {[0]}, {E}. Returns false on a malformed key.
bool parse_key(const std::string& key, std::vector<Step>& steps) {
  size_t i = 0;
  while (i < key.size()) {
    Step name;
    while (i < key.size() && is_name_char(key[i])) name.name += key[i++];
    if (name.name.empty()) return false;
    steps.push_back(name);
    while (i < key.size() && key[i] == '[') {
      const size_t close = key.find(']', i);
      if (close == std::string::npos || close == i + 1 || close > i + 10) return false;
      const std::string digits = key.substr(i + 1, close - i - 1);
      for (char c : digits)
        if (!std::isdigit(static_cast<unsigned char>(c))) return false;
      steps.push_back(Step{"", std::stoul(digits)});
      i = close + 1;
    }
    if (i == key.size()) break;
    if (key[i] != '.' || i + 1 == key.size()) return false;
    ++i;
  }
  return !steps.empty();
}

std::string path_of(const std::vector<Step>& steps, size_t count) {
  std::string path;
  for (size_t k = 0; k < count; ++k)
    path = steps[k].name.empty() ? item_key(path, steps[k].index) : child_key(path, steps[k].name);
  return path;
}

}  // namespace

std::map<std::string, std::string> apply_overrides(YAML::Node& root,
                                                   const std::vector<std::string>& overrides,
                                                   const std::string& file) {
  std::map<std::string, std::string> override_of_key;
  for (const std::string& text : overrides) {
    auto fail = [&](const std::string& reason) {
      throw InputError(printable(file + ": override '" + text + "': " + reason));
    };
    const size_t eq = text.find('=');
    if (eq == std::string::npos) fail("expected key=value");
    std::vector<Step> steps;
    if (!parse_key(text.substr(0, eq), steps))
      fail("malformed key (expected e.g. mesh.order or materials[0].E)");
    if (!steps.front().name.empty() && root.IsNull()) root = YAML::Node(YAML::NodeType::Map);
    YAML::Node value;
    try {
      value = YAML::Load(text.substr(eq + 1));
    } catch (const YAML::Exception& e) {
      fail("the value is not valid YAML: " + e.msg);
    }

    // Walk down to the parent of the last step, creating missing maps. `node.reset(x)`
    // rebinds the handle; `node = x` would overwrite the tree node instead.
    YAML::Node node = root;
    for (size_t k = 0; k < steps.size(); ++k) {
      const Step& step = steps[k];
      const bool last = k + 1 == steps.size();
      const std::string here = path_of(steps, k + 1);
      if (step.name.empty()) {
        if (!node.IsSequence()) fail(path_of(steps, k) + " is not a list");
        if (step.index >= node.size())
          fail(here + " does not exist (" + path_of(steps, k) + " has " +
               std::to_string(node.size()) + " entries)");
      } else {
        if (node.IsNull()) node = YAML::Node(YAML::NodeType::Map);
        if (!node.IsMap()) fail((k ? path_of(steps, k) : "the deck") + " is not a map");
        if (!last && !node[step.name]) node[step.name] = YAML::Node(YAML::NodeType::Map);
      }
      if (last) {
        if (step.name.empty())
          node[step.index] = value;
        else
          node[step.name] = value;
      } else {
        YAML::Node next = step.name.empty() ? node[step.index] : node[step.name];
        node.reset(next);
      }
    }
    override_of_key[path_of(steps, steps.size())] = text;
  }
  return override_of_key;
}

}  // namespace hs
