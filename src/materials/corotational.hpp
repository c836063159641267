// Corotational linear elasticity (docs/formulation.md, "Corotational"), model corotational.
#pragma once

#include "materials/elastic_constants.hpp"

namespace hs {

// F = R S, psi = mu |S - I|^2 + lambda/2 tr(S - I)^2, P = R dpsi/dS (H = F - I).
// psi = +inf, P = A = NaN for det F <= 0; A = 0 unless with_tangent.
StressResult corotational(double mu, double lambda, const Mat3& H, bool with_tangent);

inline constexpr char kCorotationalName[] = "corotational";
using CorotationalLaw = ConstantsOnlyLaw<kCorotationalName, corotational>;

}  // namespace hs
