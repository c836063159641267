#include "materials/registry.hpp"

#include <algorithm>
#include <stdexcept>

#include "materials/corotational.hpp"
#include "materials/gent.hpp"
#include "materials/linear_elastic.hpp"
#include "materials/mooney_rivlin.hpp"
#include "materials/neo_hookean.hpp"
#include "materials/saint_venant_kirchhoff.hpp"
#include "materials/yeoh.hpp"

namespace hs {
namespace {

// The one list of the laws (their order is that of error messages and printed lists).
const std::vector<MaterialLawEntry>& registered_laws() {
  static const std::vector<MaterialLawEntry> laws = {
      registry_entry<LinearElasticLaw>(),
      registry_entry<CorotationalLaw>(),
      registry_entry<SaintVenantKirchhoffLaw>(),
      registry_entry<NeoHookeanLaw>(),
      registry_entry<MooneyRivlinLaw>(),
      registry_entry<GentLaw>(),
      registry_entry<YeohLaw>(),
  };
  return laws;
}

bool reads(const MaterialLawEntry& law, const std::string& name) {
  for (const auto& k : law.keys)
    if (k.name == name) return true;
  return false;
}

const MaterialLawEntry* entry_of(const std::string& model) {
  for (const auto& law : registered_laws())
    if (law.name == model) return &law;
  return nullptr;
}

}  // namespace

std::vector<std::string> material_law_names() {
  std::vector<std::string> names;
  for (const auto& law : registered_laws()) names.push_back(law.name);
  return names;
}

std::vector<std::string> material_law_keys() {
  std::vector<std::string> keys;
  for (const auto& law : registered_laws())
    for (const auto& k : law.keys)
      if (!contains(keys, k.name)) keys.push_back(k.name);
  return keys;
}

std::vector<std::string> material_laws_reading(const std::string& name) {
  std::vector<std::string> laws;
  for (const auto& law : registered_laws())
    if (reads(law, name)) laws.push_back(law.name);
  return laws;
}

std::shared_ptr<const MaterialLaw> parse_material_law(const DeckReader& r, const YAML::Node& node,
                                                      const std::string& key,
                                                      const std::string& model,
                                                      const std::vector<std::string>& caller_keys) {
  const MaterialLawEntry* entry = entry_of(model);
  const std::string model_key = child_key(key, "model");
  if (!entry) {
    const std::string reason =
        "unknown name '" + model + "' (valid: " + join(material_law_names()) + ")";
    if (node.IsMap() && node["model"]) r.fail(model_key, node["model"], reason);
    r.fail(model_key, reason);
  }
  if (!node.IsMap()) r.fail(key, node, "expected a map");
  // A key of another law is named as such, rather than as unknown.
  for (const auto& item : node) {
    const std::string name = item.first.Scalar();
    if (contains(caller_keys, name) || reads(*entry, name)) continue;
    const std::vector<std::string> users = material_laws_reading(name);
    if (!users.empty())
      r.fail(child_key(key, name), item.second,
             std::string(users.size() == 1 ? "only used by model " : "only used by models ") +
                 join(users));
  }
  std::vector<std::string> known = caller_keys;
  for (const auto& k : entry->keys) known.push_back(k.name);
  r.check_map(node, key, known);
  return entry->parse(r, node, key);
}

void print_material_law(YAML::Emitter& out, const MaterialLaw& law) {
  const MaterialLawEntry* entry = entry_of(law.name());
  if (!entry) throw std::logic_error("material law '" + law.name() + "' is not registered");
  entry->print(out, law);
}

std::string material_laws_markdown() {
  // Each declaration once, with the laws that declare it so.
  std::vector<std::pair<MaterialLawKey, std::vector<std::string>>> rows;
  for (const auto& law : registered_laws())
    for (const auto& k : law.keys) {
      auto row =
          std::find_if(rows.begin(), rows.end(), [&](const auto& r) { return r.first == k; });
      if (row == rows.end()) row = rows.insert(rows.end(), {k, {}});
      row->second.push_back(law.name);
    }
  const std::vector<std::string> all = material_law_names();
  const auto quoted = [](const std::vector<std::string>& names) {
    std::vector<std::string> words;
    for (const auto& name : names) words.push_back("`" + name + "`");
    return join(words);
  };
  std::string text = "| key | models | type | default | meaning |\n|---|---|---|---|---|\n";
  for (const auto& [k, laws] : rows) {
    std::vector<std::string> others;  // the laws without this declaration
    for (const auto& name : all)
      if (!contains(laws, name)) others.push_back(name);
    const std::string models = others.empty()                ? "all"
                               : others.size() < laws.size() ? "all but " + quoted(others)
                                                             : quoted(laws);
    text += "| `" + k.name + "` | " + models + " | " + k.type + " | " + k.default_value + " | " +
            k.meaning + " |\n";
  }
  return text;
}

std::shared_ptr<const MaterialLaw> make_material_law(
    const std::string& model, const std::map<std::string, double>& parameters) {
  YAML::Node node(YAML::NodeType::Map);
  for (const auto& [name, value] : parameters) node[name] = format_number(value);
  const DeckReader r("(" + model + " parameters)", {});
  return parse_material_law(r, node, "material", model, {});
}

}  // namespace hs
