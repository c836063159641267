// Closed-form solutions of the verification decks (docs/verification.md derives each one;
// ../shared-free: every formula is written out here). u(X; s) is the displacement at
// reference point X under load factor s.
#pragma once

#include <array>
#include <memory>
#include <string>

#include "deck/config.hpp"

namespace hs {

class ExactSolution {
 public:
  virtual ~ExactSolution() = default;
  virtual std::array<double, 3> displacement(const std::array<double, 3>& X, double s) const = 0;
};

// nullptr when the deck has no exact solution (exact.type none). Throws InputError for a
// missing parameter, naming the key.
std::unique_ptr<ExactSolution> make_exact_solution(const Config& config);

// Thick-walled sphere, linear elasticity, internal pressure p (Lame):
//   u_r = p a^3 / (E (b^3 - a^3)) [(1 - 2 nu) r + (1 + nu) b^3 / (2 r^2)].
double lame_sphere_radial_displacement(double r, double a, double b, double p, double E, double nu);

// Incompressible neo-Hookean thick sphere: inner pressure over mu at inner stretch la.
double neo_hookean_sphere_pressure(double la, double A, double B);

// Euler-Bernoulli tip deflection of a cantilever of square section h under self-weight.
double cantilever_tip_deflection(double rho, double g, double L, double h, double E);

// Elastica, inextensible cantilever under uniform load: v/L at beta = q L^3 / (E I),
// interpolated in the published table (beta 1..16).
double elastica_uniform_load(double beta);

}  // namespace hs
