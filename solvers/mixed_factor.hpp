// The direct solve of a nodal-pressure body's tangent through its mixed form (docs/formulation.md,
// "The mixed factorization"). The tangent J = K + G^T D G (solvers/nodal_pressure.hpp) joins a
// node to its neighbours' neighbours; with the patch pressures' increments w = D G du as
// unknowns of their own it is the saddle-point system
//   [ K   G^T     ] [du]   [b]
//   [ G  -D^-1    ] [w ] = [0],
// whose stencil is the element's (a node and its neighbours) and whose factors, with one
// unknown more per node, are about a third smaller than J's. Eliminating w gives J du = b
// exactly, so the solve is J's to round-off.
//
// The PETSc preconditioner type `hs_mixed` factors that system (MUMPS, L D L^T or LU) and
// applies it: with KSPPREONLY it is J's direct solve. The system is the matrix the problem
// composes on the tangent (kMixedTangentKey), filled with every tangent; its rows on each
// rank are the rank's displacement rows, then its nodes' pressure rows.
#pragma once

#include <petscksp.h>

namespace hs {

inline constexpr const char* kMixedFactorType = "hs_mixed";
// The name under which the problem composes the mixed system on the tangent's matrix.
inline constexpr const char* kMixedTangentKey = "hs_mixed_tangent";

// Makes `hs_mixed` a preconditioner type PETSc knows (once; after PetscInitialize).
void register_mixed_factor();

// The number of negative eigenvalues of J that the last factorization found (the mixed
// system's negative pivots less its pressure block's negative entries: Sylvester's law of
// inertia through the Schur complement), or -1 if not a factorization by MUMPS.
int mixed_factor_negative_pivots(PC pc);

}  // namespace hs
