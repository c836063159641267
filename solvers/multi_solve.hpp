// Several right-hand sides against one operator: the bordered Newton and the controller solve
// for R, every cavity's g_c and every liquid's q_h with the same factorization.
#pragma once

#include <petscksp.h>

#include <vector>

namespace hs {

// x[j] = K^-1 b[j] with the KSP's operators (set up here if they are not yet). With a direct
// factorization (KSP preonly) all columns go through the factors in one MatMatSolve: MUMPS
// then traverses its factors once for all of them, where one KSPSolve each traverses them
// once per column (docs/control.md measures it). Other KSPs solve one column at a time.
// Returns false when a solve failed (a failed factorization, an iterative solve that
// diverged); adds the Krylov iterations to *iterations when given.
bool solve_columns(KSP ksp, const std::vector<Vec>& b, const std::vector<Vec>& x,
                   int* iterations = nullptr);

}  // namespace hs
