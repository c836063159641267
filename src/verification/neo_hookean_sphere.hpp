// Incompressible neo-Hookean thick sphere A <= R <= B inflated to inner stretch `stretch`
// (the inner radius is prescribed, growing linearly with the load factor).
#pragma once

#include "verification/registry.hpp"

namespace hs {

// Inner pressure over mu at inner stretch la.
double neo_hookean_sphere_pressure(double la, double A, double B);

// exact.type neo_hookean_sphere: parameters A, B, stretch; one material (its mu). Checked by
// the inner pressure, from the reactions on the node group `inner`, against the curve.
ExactSolutionType neo_hookean_sphere_type();

}  // namespace hs
