#include "deck/exact_section.hpp"

#include "common/error.hpp"
#include "materials/material.hpp"
#include "verification/registry.hpp"

namespace hs {

void parse_exact_section(const DeckReader& r, const YAML::Node& node, Config& c) {
  r.check_map(node, "exact", {"type", "parameters"});
  std::vector<std::string> names = {"none"};
  for (const auto& name : exact_solution_names()) names.push_back(name);
  const std::string type = node["type"] ? one_of(r, node["type"], "exact.type", names) : "none";
  if (const auto n = node["parameters"]) c.exact.parameters = r.number_map(n, "exact.parameters");
  const auto& parameters = c.exact.parameters;
  if (type == "none") {
    if (!parameters.empty()) {
      const std::string& name = parameters.begin()->first;
      r.fail(child_key("exact.parameters", name), node["parameters"][name],
             "unknown to exact solution 'none' (takes no parameters)");
    }
    return;
  }
  c.exact.type = &exact_solution_type(type);
  try {
    check_exact_parameters(*c.exact.type, parameters);
  } catch (const ExactInputError& e) {
    // The line of the parameter when the deck gives it, else of the section.
    const std::string name = e.key().substr(e.key().rfind('.') + 1);
    const YAML::Node given = node["parameters"] ? node["parameters"][name] : YAML::Node();
    r.fail(e.key(), given ? given : node, e.what());
  }
}

std::unique_ptr<const ExactSolution> make_exact_solution(const Config& c) {
  if (!c.exact.type) return nullptr;
  ExactSetting setting;
  for (const auto& m : c.materials) {
    const ElasticConstants& k = m.law->elastic_constants();
    setting.materials.push_back({m.group, k.E, k.nu, k.mu, k.lambda, m.density});
  }
  setting.gravity = c.gravity;
  try {
    return make_exact_solution(*c.exact.type, c.exact.parameters, setting);
  } catch (const ExactInputError& e) {
    throw InputError(c.deck_path + ": " + e.key() + ": " + e.what());
  }
}

}  // namespace hs
