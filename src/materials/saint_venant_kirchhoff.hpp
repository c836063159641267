// Saint Venant-Kirchhoff (docs/formulation.md, "Saint Venant-Kirchhoff"), model
// saint_venant_kirchhoff.
#pragma once

#include "materials/elastic_constants.hpp"

namespace hs {

// E = (F^T F - I)/2, S = lambda tr(E) I + 2 mu E, P = F S (H = F - I).
// psi = +inf, P = A = NaN for det F <= 0; A = 0 unless with_tangent.
StressResult saint_venant_kirchhoff(double mu, double lambda, const Mat3& H, bool with_tangent);

inline constexpr char kSaintVenantKirchhoffName[] = "saint_venant_kirchhoff";
using SaintVenantKirchhoffLaw = ConstantsOnlyLaw<kSaintVenantKirchhoffName, saint_venant_kirchhoff>;

}  // namespace hs
