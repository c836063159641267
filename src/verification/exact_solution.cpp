#include "verification/exact_solution.hpp"

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

const ExactMaterial& material_of(const ExactSetting& setting, const std::string& group,
                                 const std::string& solution) {
  for (const auto& m : setting.materials)
    if (m.group == group) return m;
  throw ExactInputError(
      "materials", "exact solution '" + solution + "' needs a material for group '" + group + "'");
}

}  // namespace hs
