// The pressure's patch test at exact incompressibility: a block on three symmetry planes pulled
// by a dead traction on its top into a homogeneous uniaxial stretch, its pressure uniform.
#pragma once

#include "verification/registry.hpp"

namespace hs {

// The stretch lambda of an incompressible neo-Hookean body under the dead uniaxial traction t
// (force per reference area): mu (lambda - 1 / lambda^2) = t.
double incompressible_uniaxial_stretch(double t_over_mu);

// exact.type stretched_block: parameter t (the traction on the top, Pa, as in loads.traction);
// one neo-Hookean material of nu = 0.5. The run reports the errors of the displacement and of
// the elements' pressure, both zero but for the solver's tolerance on any mesh.
ExactSolutionType stretched_block_type();

}  // namespace hs
