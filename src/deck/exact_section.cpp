#include "deck/exact_section.hpp"

#include "common/error.hpp"
#include "deck/section_keys.hpp"
#include "materials/material.hpp"
#include "verification/registry.hpp"

namespace hs {

namespace {

std::vector<std::string> exact_type_names() {
  std::vector<std::string> names = {"none"};
  for (const auto& name : exact_solution_names()) names.push_back(name);
  return names;
}

}  // namespace

const KeyTable<ExactConfig>& exact_keys() {
  static const KeyTable<ExactConfig> keys = {
      custom_key<ExactConfig>(
          "type", "name", "`none`",
          "an exact solution to compare with (summary.json `error`) and to take `exact: true` "
          "boundary values from",
          [](const DeckReader& r, const YAML::Node& n, const std::string& key, ExactConfig& e,
             const Config&) {
            const std::string type = one_of(r, n, key, exact_type_names());
            e.type = type == "none" ? nullptr : &exact_solution_type(type);
          },
          [](YAML::Emitter& out, const ExactConfig& e, const Config&) {
            out << (e.type ? e.type->name : "none");
          }),
      custom_key<ExactConfig>(
          "parameters", "map name: number", "none", "exactly the parameters of the chosen solution",
          [](const DeckReader& r, const YAML::Node& n, const std::string& key, ExactConfig& e,
             const Config&) { e.parameters = r.number_map(n, key); },
          [](YAML::Emitter& out, const ExactConfig& e, const Config&) {
            out << YAML::Flow << YAML::BeginMap;
            for (const auto& [name, value] : e.parameters)
              out << YAML::Key << name << YAML::Value << format_number(value);
            out << YAML::EndMap;
          }),
  };
  return keys;
}

void parse_exact_section(const DeckReader& r, const YAML::Node& node, Config& c) {
  read_keys(r, node, "exact", exact_keys(), c.exact, c);
  const auto& parameters = c.exact.parameters;
  if (!c.exact.type) {
    if (!parameters.empty()) {
      const std::string& name = parameters.begin()->first;
      r.fail(child_key("exact.parameters", name), node["parameters"][name],
             "unknown to exact solution 'none' (takes no parameters)");
    }
    return;
  }
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
    setting.materials.push_back({m.group, k.E, k.nu, k.mu, k.lambda, m.density, m.law->name()});
  }
  setting.gravity = c.gravity;
  try {
    return make_exact_solution(*c.exact.type, c.exact.parameters, setting);
  } catch (const ExactInputError& e) {
    throw InputError(c.deck_path + ": " + e.key() + ": " + e.what());
  }
}

}  // namespace hs
