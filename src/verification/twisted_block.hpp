// A manufactured solution of exact incompressibility: the cube 0 <= X <= H twisted about its
// vertical axis, with a volumetric stress of its own; every face is free of traction in it, so
// a run holds the bottom alone.
#pragma once

#include "verification/registry.hpp"

namespace hs {

// exact.type twisted_block: parameters H (the cube's side), twist (the largest angle, in
// radians) and q (the volumetric stress's amplitude over mu); one neo-Hookean material of
// nu = 0.5. The run adds the body force that makes it an equilibrium and reports the errors
// of the displacement and of the elements' pressure.
ExactSolutionType twisted_block_type();

}  // namespace hs
