// Compressible neo-Hookean (docs/formulation.md, "Neo-Hookean"), model neo_hookean.
#pragma once

#include "materials/elastic_constants.hpp"

namespace hs {

// psi = mu/2 (I1 - 3) - mu ln J + lambda/2 (ln J)^2 (H = F - I).
// psi = +inf, P = A = NaN for det F <= 0; A = 0 unless with_tangent.
StressResult neo_hookean(double mu, double lambda, const Mat3& H, bool with_tangent);

inline constexpr char kNeoHookeanName[] = "neo_hookean";
using NeoHookeanLaw = ConstantsOnlyLaw<kNeoHookeanName, neo_hookean, true>;

}  // namespace hs
