// Thick-walled sphere a <= r <= b of a linear elastic material under internal pressure p.
#pragma once

#include "verification/registry.hpp"

namespace hs {

// Lame: u_r = p a^3 / (E (b^3 - a^3)) [(1 - 2 nu) r + (1 + nu) b^3 / (2 r^2)].
double lame_sphere_radial_displacement(double r, double a, double b, double p, double E, double nu);

// exact.type lame_sphere: parameters a, b, p; one material (its E, nu).
ExactSolutionType lame_sphere_type();

}  // namespace hs
