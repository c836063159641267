// The deck's `exact` section (docs/decks.md): the name of an exact solution and its
// parameters, handed to the registry of src/verification/, which knows both.
#pragma once

#include <yaml-cpp/yaml.h>

#include <memory>

#include "common/deck_reader.hpp"
#include "deck/config.hpp"
#include "verification/exact_solution.hpp"

namespace hs {

// Fills c.exact from the map `node` of section `exact` (left empty with type none); the
// parameters' names and values are checked here, errors as "FILE: exact.parameters.NAME:
// reason (line N)".
void parse_exact_section(const DeckReader& r, const YAML::Node& node, Config& c);

// The deck's exact solution built from its parameters and the deck's numbers (materials,
// gravity), or null without one. Throws InputError "FILE: KEY: reason" for a deck whose
// setting the solution cannot use (e.g. lame_sphere with several materials).
std::unique_ptr<const ExactSolution> make_exact_solution(const Config& c);

}  // namespace hs
