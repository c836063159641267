#include "verification/registry.hpp"

#include <algorithm>

#include "common/deck_reader.hpp"
#include "verification/bimaterial_bar.hpp"
#include "verification/cantilever_gravity.hpp"
#include "verification/hydrostatic_block.hpp"
#include "verification/lame_sphere.hpp"
#include "verification/neo_hookean_sphere.hpp"
#include "verification/stretched_block.hpp"
#include "verification/twisted_block.hpp"

namespace hs {

const std::vector<ExactSolutionType>& exact_solution_types() {
  // One line per exact solution.
  static const std::vector<ExactSolutionType> types = {
      lame_sphere_type(),        cantilever_gravity_type(), hydrostatic_block_type(),
      neo_hookean_sphere_type(), bimaterial_bar_type(),     twisted_block_type(),
      stretched_block_type(),
  };
  return types;
}

std::vector<std::string> exact_solution_names() {
  std::vector<std::string> names;
  for (const auto& type : exact_solution_types()) names.push_back(type.name);
  return names;
}

const ExactSolutionType& exact_solution_type(const std::string& name) {
  const auto& types = exact_solution_types();
  const auto type = std::find_if(types.begin(), types.end(),
                                 [&](const ExactSolutionType& t) { return t.name == name; });
  if (type == types.end())
    throw ExactInputError("exact.type", "unknown exact solution '" + name +
                                            "' (valid: " + join(exact_solution_names()) + ")");
  return *type;
}

void check_exact_parameters(const ExactSolutionType& type, const ExactParameterMap& parameters) {
  const std::string takes = "exact solution '" + type.name + "' (takes " +
                            (type.parameters.empty() ? "no parameters" : join(type.parameters)) +
                            ")";
  for (const auto& p : type.parameters)
    if (!parameters.count(p))
      throw ExactInputError("exact.parameters." + p, "required by " + takes);
  for (const auto& entry : parameters)
    if (!contains(type.parameters, entry.first))
      throw ExactInputError("exact.parameters." + entry.first, "unknown to " + takes);
  type.check(ExactParameters(type.name, parameters));
}

std::unique_ptr<const ExactSolution> make_exact_solution(const ExactSolutionType& type,
                                                         const ExactParameterMap& parameters,
                                                         const ExactSetting& setting) {
  check_exact_parameters(type, parameters);
  return type.make(ExactParameters(type.name, parameters), setting);
}

}  // namespace hs
