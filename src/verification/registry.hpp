// The registry of exact solutions: one entry per solution (registry.cpp lists them, each
// defined in its own file of this folder). The deck layer (src/deck/exact_section.cpp) hands
// the deck's `exact:` section to it; nothing else knows the names.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "verification/exact_solution.hpp"

namespace hs {

struct ExactSolutionType {
  std::string name;                     // the deck's exact.type
  std::vector<std::string> parameters;  // exact.parameters, all required
  // Checks the values of parameters known to be exactly `parameters` (when the deck is
  // parsed); throws ExactInputError.
  void (*check)(const ExactParameters&);
  // Builds the solution from checked parameters and the deck's numbers (when the run
  // starts); throws ExactInputError for a setting it cannot use (e.g. several materials).
  std::unique_ptr<ExactSolution> (*make)(const ExactParameters&, const ExactSetting&);
};

// Every exact solution, in the registry's order, and their names.
const std::vector<ExactSolutionType>& exact_solution_types();
std::vector<std::string> exact_solution_names();

// The named solution's entry; ExactInputError with key "exact.type" for an unknown name (the
// message lists the valid ones).
const ExactSolutionType& exact_solution_type(const std::string& name);

// Checks that `parameters` are exactly those of `type` and their values; ExactInputError
// with key "exact.parameters.NAME" for a missing, unknown or bad one.
void check_exact_parameters(const ExactSolutionType& type, const ExactParameterMap& parameters);

// check_exact_parameters, then the solution.
std::unique_ptr<const ExactSolution> make_exact_solution(const ExactSolutionType& type,
                                                         const ExactParameterMap& parameters,
                                                         const ExactSetting& setting);

}  // namespace hs
