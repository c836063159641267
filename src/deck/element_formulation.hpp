// Which element solves a material's body: the choice of the `formulation` key resolved against
// the material's compressibility and the mesh's order (docs/formulation.md, "Nearly
// incompressible bodies"), with the reason printed beside the material and, for an element
// that locks, the error to expect.
#pragma once

#include <string>

#include "deck/config.hpp"

namespace hs {

// Poisson's ratio from which auto picks a locking-free element (kappa/mu >= 49.7): F-bar on
// P2, nodal pressure on P1. There the displacement element's error on a thick sphere passes
// 8 % on P1 (docs/stiff_cases.md, "Locking").
constexpr double kNearlyIncompressibleNu = 0.49;

struct FormulationChoice {
  ElementFormulation formulation = ElementFormulation::displacement;
  std::string reason;   // e.g. "auto: nu = 0.4999 >= 0.49 on P2"
  std::string warning;  // empty, or what a locking element costs here
  std::string error;    // empty, or why the asked formulation cannot run (an input error)
  std::string error_key = "formulation";  // the material's key the error names
};

// `asked` as the deck gives it (automatic included), Poisson's ratio nu of the material's
// small-strain constants (0.5: incompressible, on the nodal-pressure element on P1 and the F-bar
// element of a finite-strain law on P2, whose volume multipliers keep it), the mesh's element
// order (1 or 2), and whether the law's energy has
// the volumetric term k/2 (ln J)^2 that the nodal-pressure element integrates per node.
FormulationChoice choose_formulation(ElementFormulation asked, double nu, int order,
                                     bool law_has_volumetric_term, bool law_small_strain);

}  // namespace hs
