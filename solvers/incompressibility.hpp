// Exactly incompressible bodies (nu = 0.5) by an augmented Lagrangian (docs/formulation.md,
// "Exactly incompressible bodies"): the nodal-pressure element keeps a multiplier per patch on
// top of a penalty bulk modulus (solvers/nodal_pressure.hpp); each solve is repeated with the
// multipliers raised, lambda_a += kbar_a ln J_a, until no patch's volume changes by more than
// kVolumeTolerance. Both Newton solvers solve through it, so every stepper and the controller
// get it; a body without such a material solves once, as before.
#pragma once

#include <functional>

#include "solvers/problem.hpp"
#include "solvers/stepping/nonlinear_solver.hpp"

namespace hs {

// The largest |ln J_a| of a patch that a converged solve leaves: the volume kept to 1e-8 of
// itself, where the penalty alone (kappa = 5000 mu) leaves about 1e-4 at p/mu = 0.5.
inline constexpr double kVolumeTolerance = 1e-8;
// Raises before a solve is given up (each one divides the volume change by about
// kappa / mu on a well-posed body; docs/formulation.md has the measured counts).
inline constexpr int kMaxMultiplierRaises = 20;

// The F-bar element's penalty grows within a solve (docs/formulation.md, "Exactly
// incompressible bodies"): each solve starts at kFbarPenaltyStart of the law's
// (kIncompressiblePenalty mu), soft enough that Newton's steps on thin walls do not invert
// the nearly rigid volume, and a raise that divides the volume change by less than
// 1 / kSlowRaise multiplies it by kPenaltyGrowth, up to the law's, at which it is left for
// every other use of the tangent (the controller's compliance). The nodal-pressure element
// keeps its law's penalty: its raises contract by only about 5 at it.
inline constexpr double kFbarPenaltyStart = 0.01;
inline constexpr double kPenaltyGrowth = 10;
inline constexpr double kSlowRaise = 0.25;

// `solve` (a Newton solve at the multipliers as they are, from u) repeated until the volumes
// are kept; its iterations summed. On failure the multipliers are put back as they were, so
// a cut-back step starts from them again. monitor: a line per raise (the solver's option
// hs_volume_monitor, from the deck or the command line). Collective.
NewtonResult solve_keeping_volumes(Problem& problem, Vec u,
                                   const std::function<NewtonResult()>& solve, bool monitor);

}  // namespace hs
