// Cantilever of square section h and length L along +x, clamped at x = 0, under its own
// weight (gravity along -z): Euler-Bernoulli at small load, the inextensible elastica beyond.
#pragma once

#include "verification/registry.hpp"

namespace hs {

// Euler-Bernoulli tip deflection under self-weight: 3 rho g L^4 / (2 E h^2).
double cantilever_tip_deflection(double rho, double g, double L, double h, double E);

// Elastica, inextensible cantilever under uniform load: v/L at beta = q L^3 / (E I).
double elastica_uniform_load(double beta);

// exact.type cantilever_gravity: parameters L, h; one material (its E and density), the
// deck's gravity. Checked by the mean deflection of the node group `tip`; the L2 error of
// the displacement, exact only along the axis, is reported but not meaningful.
ExactSolutionType cantilever_gravity_type();

}  // namespace hs
