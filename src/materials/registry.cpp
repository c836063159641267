#include "materials/registry.hpp"

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

}  // namespace

std::vector<std::string> material_law_names() {
  std::vector<std::string> names;
  for (const auto& law : registered_laws()) names.push_back(law.name);
  return names;
}

std::vector<std::string> material_law_keys() {
  std::vector<std::string> keys;
  for (const auto& law : registered_laws())
    for (const auto& name : law.keys)
      if (!contains(keys, name)) keys.push_back(name);
  return keys;
}

std::shared_ptr<const MaterialLaw> parse_material_law(const DeckReader& r, const YAML::Node& node,
                                                      const std::string& key,
                                                      const std::string& model,
                                                      const std::vector<std::string>& caller_keys) {
  const MaterialLawEntry* entry = nullptr;
  for (const auto& law : registered_laws())
    if (law.name == model) entry = &law;
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
    if (contains(caller_keys, name) || contains(entry->keys, name)) continue;
    std::vector<std::string> users;
    for (const auto& law : registered_laws())
      if (contains(law.keys, name)) users.push_back(law.name);
    if (!users.empty())
      r.fail(child_key(key, name), item.second,
             std::string(users.size() == 1 ? "only used by model " : "only used by models ") +
                 join(users));
  }
  std::vector<std::string> known = caller_keys;
  known.insert(known.end(), entry->keys.begin(), entry->keys.end());
  r.check_map(node, key, known);
  return entry->parse(r, node, key);
}

std::shared_ptr<const MaterialLaw> make_material_law(
    const std::string& model, const std::map<std::string, double>& parameters) {
  YAML::Node node(YAML::NodeType::Map);
  for (const auto& [name, value] : parameters) node[name] = format_number(value);
  const DeckReader r("(" + model + " parameters)", {});
  return parse_material_law(r, node, "material", model, {});
}

}  // namespace hs
