// Errors of a computed displacement against the deck's exact solution, and the derived
// quantities an exact solution asks the run to measure (tip deflection, pressure from
// reactions). Called by the run (solvers/simulation.cpp) after the solve; the closed forms
// themselves are pure functions in src/verification/.
#pragma once

#include <nlohmann/json.hpp>

#include "solvers/problem.hpp"
#include "verification/exact_solution.hpp"

namespace hs {

struct ErrorNorms {
  double l2_absolute = 0;  // ||u_h - u||_L2
  double l2_relative = 0;  // ||u_h - u||_L2 / ||u||_L2
};

// Integrated element by element with a quadrature rule of degree 2 order + 2, summed over ranks.
ErrorNorms displacement_error(const Problem& problem, Vec u, const ExactSolution& exact, double s);

// The error of the elements' pressure -tr(sigma)/3 (the stress written per element, constant
// in each) against the exact solution's (ExactSolution::pressure), integrated as
// displacement_error. Collective.
ErrorNorms pressure_error(const Problem& problem, Vec u, const ExactSolution& exact);

// The exact solution's verification quantities at load factor s (ExactSolution::verification),
// from the measures it asks for taken on u; a null object when it asks for none.
nlohmann::json verification_quantities(const ExactSolution& exact, Problem& problem, Vec u,
                                       double s);

}  // namespace hs
