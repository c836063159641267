#include "verification/exact_solution.hpp"

#include <cmath>

#include "common/deck_reader.hpp"

namespace hs {

double ExactParameters::positive(const std::string& name) const {
  const double value = (*this)[name];
  if (!(value > 0)) fail(name, "must be > 0, got " + format_number(value));
  return value;
}

double ExactParameters::greater_than(const std::string& name, const std::string& smaller) const {
  const double value = (*this)[name], bound = (*this)[smaller];
  if (!(value > bound))
    fail(name,
         "must be > " + smaller + " = " + format_number(bound) + ", got " + format_number(value));
  return value;
}

void ExactParameters::fail(const std::string& name, const std::string& reason) const {
  throw ExactInputError("exact.parameters." + name,
                        reason + " (exact solution '" + solution_ + "')");
}

const ExactMaterial& only_material(const ExactSetting& setting, const std::string& solution) {
  if (setting.materials.size() != 1)
    throw ExactInputError("materials", "exact solution '" + solution +
                                           "' needs exactly one material, the deck has " +
                                           std::to_string(setting.materials.size()));
  return setting.materials[0];
}

const ExactMaterial& only_incompressible_neo_hookean(const ExactSetting& setting,
                                                     const std::string& solution) {
  const ExactMaterial& m = only_material(setting, solution);
  if (m.model != "neo_hookean")
    throw ExactInputError(
        "materials", solution + " is a solution of the neo_hookean law, got '" + m.model + "'");
  if (m.nu != 0.5)
    throw ExactInputError("materials", solution + " is exactly incompressible: it needs nu = 0.5");
  return m;
}

const ExactMaterial& material_of(const ExactSetting& setting, const std::string& group,
                                 const std::string& solution) {
  for (const auto& m : setting.materials)
    if (m.group == group) return m;
  throw ExactInputError(
      "materials", "exact solution '" + solution + "' needs a material for group '" + group + "'");
}

namespace {

// The first number in `value` (a JSON tree) that is not finite, by its key; "" when none.
std::string non_finite_key(const nlohmann::json& value, const std::string& key) {
  if (value.is_number()) return std::isfinite(value.get<double>()) ? "" : key;
  if (value.is_object())
    for (const auto& [name, item] : value.items())
      if (auto bad = non_finite_key(item, name); !bad.empty()) return bad;
  if (value.is_array())
    for (const auto& item : value)
      if (auto bad = non_finite_key(item, key); !bad.empty()) return bad;
  return "";
}

}  // namespace

std::string non_finite_reference(const ExactSolution& solution, const std::vector<double>& x) {
  for (size_t n = 0; n < x.size() / 3; ++n) {
    const std::array<double, 3> X{x[3 * n], x[3 * n + 1], x[3 * n + 2]};
    const auto u = solution.displacement(X, 1.0);
    if (!(std::isfinite(u[0]) && std::isfinite(u[1]) && std::isfinite(u[2])))
      return "its displacement at the node (" + format_number(X[0]) + ", " + format_number(X[1]) +
             ", " + format_number(X[2]) + ") is not finite";
  }
  const std::vector<double> at_rest(solution.measures().size(), 0.0);
  const std::string key = non_finite_key(solution.verification(at_rest, 1.0), "");
  if (!key.empty()) return "its verification quantity " + key + " is not finite";
  return "";
}

}  // namespace hs
