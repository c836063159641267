// Errors of a computed displacement against an exact solution, and the derived quantities
// the verification decks report (tip deflection, cavity pressure).
#pragma once

#include <nlohmann/json.hpp>

#include "solvers/exact_solution.hpp"
#include "solvers/problem.hpp"

namespace hs {

struct ErrorNorms {
  double l2_absolute = 0;  // ||u_h - u||_L2
  double l2_relative = 0;  // ||u_h - u||_L2 / ||u||_L2
};

// Integrated element by element with a quadrature rule of degree 2 order + 2, summed over ranks.
ErrorNorms displacement_error(const Problem& problem, Vec u, const ExactSolution& exact, double s);

// Deck-specific results at load factor s: the cantilever's tip deflection against
// Euler-Bernoulli or the elastica, the neo-Hookean sphere's pressure against the closed-form
// curve. A null object for other decks.
nlohmann::json verification_quantities(const Config& config, Problem& problem, Vec u, double s);

}  // namespace hs
