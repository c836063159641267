// Two linear elastic materials in series along x (nu = 0), pulled by a traction t at the end.
#pragma once

#include "verification/registry.hpp"

namespace hs {

// exact.type bimaterial_bar: parameters L1 (length of the first material), t; the materials
// of groups `stiff` (0 <= x <= L1) and `soft` (beyond), their E.
ExactSolutionType bimaterial_bar_type();

}  // namespace hs
