// The five constitutive laws, one pure function each (one .cpp each, derivations in
// docs/formulation.md). Each takes the displacement gradient H = F - I (so that small strains
// keep their relative precision) and returns P, psi and, if with_tangent, A = dP/dF (else 0).
// The finite-strain laws return psi = +inf and P = A = NaN for det F <= 0.
#pragma once

#include "materials/material.hpp"

namespace hs {

// Small strain: eps = sym(H), P = sigma = lambda tr(eps) I + 2 mu eps.
StressResult linear_elastic(double mu, double lambda, const Mat3& H, bool with_tangent);

// Corotational: F = R S, psi = mu |S - I|^2 + lambda/2 tr(S - I)^2, P = R dpsi/dS.
StressResult corotational(double mu, double lambda, const Mat3& H, bool with_tangent);

// Saint Venant-Kirchhoff: E = (F^T F - I)/2, S = lambda tr(E) I + 2 mu E, P = F S.
StressResult saint_venant_kirchhoff(double mu, double lambda, const Mat3& H, bool with_tangent);

// Compressible neo-Hookean: psi = mu/2 (I1 - 3) - mu ln J + lambda/2 (ln J)^2.
StressResult neo_hookean(double mu, double lambda, const Mat3& H, bool with_tangent);

// Compressible Mooney-Rivlin on isochoric invariants:
// psi = c1 (I1b - 3) + c2 (I2b - 3) + kappa/2 (ln J)^2.
StressResult mooney_rivlin(double c1, double c2, double kappa, const Mat3& H, bool with_tangent);

// The result of a finite-strain law at det F <= 0.
StressResult inverted_result();

}  // namespace hs
