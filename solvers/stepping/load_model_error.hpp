// The error of an approximate load model in a converged state: the paper's column method for
// a liquid's weight leaves out the head above each column section and the side walls
// (docs/cavities.md, "Which fluid-weight method"). With the closed form (the liquid's pressure
// on every wall) put in the column method's place, a few Newton steps from the state, not
// taken, give the state the exact load would reach under the same controls: measured as the
// change of the tip and of each cavity, and warned of where it passes 2 % of what it changes.
// The Newton steps' tangent is the column method's (the weight follows the volume), not the
// closed form's own, so they converge linearly (a ratio of 0.1 a step on the shipped cylinder,
// 0.6 on the curled PneuNet); they stop after three once the change they leave, estimated from
// that ratio, is 1 % of the change so far, or after eight.
#pragma once

#include <petscvec.h>

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "deck/config.hpp"
#include "solvers/constraints/constraint_set.hpp"
#include "solvers/problem.hpp"
#include "solvers/stepping/nonlinear_solver.hpp"

namespace hs {

// The share of a quantity's change past which the estimate is printed as a warning.
constexpr double kLoadModelWarning = 0.02;

struct LoadModelError {
  nlohmann::json report;               // summary.json's `load_model_error` (docs/output.md)
  std::vector<double> measure_change;  // every constraint's, m^3 or m
};

// Collective, after `solver` converged at (u, s). Nothing (std::nullopt) where every load is
// exact; else the estimate, with a warning on rank 0's stderr naming `state` where it passes
// kLoadModelWarning. A later state's volumes count from the first state's end: rest_change
// (the first state's measure_change; empty in the first state) moves their targets as the
// exact load would have. u, the multipliers and the constraints' states are as they were on
// return.
std::optional<LoadModelError> load_model_error(const Config& config, Problem& problem,
                                               ConstraintSet& constraints, NonlinearSolver& solver,
                                               Vec u, double s, const std::string& state,
                                               const std::vector<double>& rest_change);

}  // namespace hs
