// Block 0 <= z <= H under its own weight, gravity along -z, stress -rho g (H - z) I.
#pragma once

#include "verification/registry.hpp"

namespace hs {

// exact.type hydrostatic_block: parameter H; one material (its density and bulk modulus),
// the deck's gravity.
ExactSolutionType hydrostatic_block_type();

}  // namespace hs
