#include "solvers/stepping/load_model_error.hpp"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>

#include "solvers/petsc_check.hpp"
#include "solvers/tip_orientation.hpp"

namespace hs {
namespace {

constexpr int kMaxSteps = 8;
constexpr double kRemainingShare = 0.01;

// |change| / |base|, or 0 where there is no base to compare with.
double share(double change, double base) {
  return std::abs(base) > 0 ? std::abs(change) / std::abs(base) : 0.0;
}

// Newton from (u, lambda) on the equations as they are now: v and the multipliers' changes,
// and the share of the change the steps left, estimated from their contraction (a step times
// r / (1 - r), r the ratio of the last two steps' lengths; 1 where they did not contract).
// False where a linear solve failed.
bool newton_from(Problem& problem, ConstraintSet& constraints, NonlinearSolver& solver, Vec u,
                 double s, Vec v, std::vector<double>& dlambda, int& steps, double& remaining) {
  VecHandle step(problem.create_vector()), total(problem.create_vector());
  HS_PETSC(VecCopy(u, v));
  const std::vector<double> lambda0 = constraints.multipliers();
  std::vector<double> lambda = lambda0, dl;
  double previous = 0;
  remaining = 1;
  for (steps = 1; steps <= kMaxSteps; ++steps) {
    if (!solver.newton_step(v, s, step, dl)) return false;
    HS_PETSC(VecAXPY(v, 1.0, step));
    for (size_t k = 0; k < lambda.size(); ++k) lambda[k] += dl[k];
    constraints.set_multipliers(lambda);
    PetscReal length = 0, change = 0;
    HS_PETSC(VecWAXPY(total, -1.0, u, v));
    HS_PETSC(VecNorm(step, NORM_2, &length));
    HS_PETSC(VecNorm(total, NORM_2, &change));
    if (change == 0) {
      remaining = 0;
      break;
    }
    const double r = previous > 0 ? length / previous : 1;
    remaining = r < 1 ? length * r / (1 - r) / change : 1;
    previous = length;
    if (steps >= 3 && remaining <= kRemainingShare) break;
  }
  steps = std::min(steps, kMaxSteps);
  dlambda.resize(lambda.size());
  for (size_t k = 0; k < lambda.size(); ++k) dlambda[k] = lambda[k] - lambda0[k];
  return true;
}

}  // namespace

std::optional<LoadModelError> load_model_error(const Config& config, Problem& problem,
                                               ConstraintSet& constraints, NonlinearSolver& solver,
                                               Vec u, double s, const std::string& state,
                                               const std::vector<double>& rest_change) {
  std::vector<int> switched;
  for (int k = 0; k < constraints.size(); ++k)
    if (constraints[k].use_exact_load(true)) switched.push_back(k);
  if (switched.empty()) return std::nullopt;

  const double t0 = MPI_Wtime();
  const ConstraintSet::Point before = constraints.point();
  if (!rest_change.empty())
    for (int k = 0; k < constraints.size(); ++k)
      if (constraints[k].control() == Constraint::Control::measure)
        constraints[k].set_target(constraints[k].target() + rest_change[k]);
  VecHandle v(problem.create_vector());
  std::vector<double> dlambda;
  int steps = 0;
  double remaining = 1;
  const bool solved = newton_from(problem, constraints, solver, u, s, v, dlambda, steps, remaining);
  for (int k : switched) constraints[k].use_exact_load(false);
  constraints.return_to(before);

  LoadModelError error;
  nlohmann::json& report = error.report;
  report = {{"against", "hydrostatic"}, {"estimated", solved}};
  int rank = 0;
  MPI_Comm_rank(problem.comm(), &rank);
  if (!solved) {
    if (rank == 0)
      std::cerr << "hydrosoft: warning: state '" << state
                << "': the fluid-weight method's error could not be estimated (a linear solve "
                   "failed)"
                << std::endl;
    return error;
  }
  report["newton_steps"] = steps;
  report["remaining"] = remaining;
  report["time_s"] = MPI_Wtime() - t0;
  for (int k = 0; k < constraints.size(); ++k)
    error.measure_change.push_back(constraints[k].measure_at(v) - constraints[k].measure());

  double largest = 0;
  std::string worst;
  char text[256];
  nlohmann::json cavities = nlohmann::json::array();
  for (int k : switched) {
    const Constraint& c = constraints[k];
    const double dp = dlambda[k], dV = error.measure_change[k];
    nlohmann::json entry = {{"cavity", c.name()},
                            {"method", c.fluid_weight()->method},
                            {"pressure_Pa", dp},
                            {"volume_ml", dV * 1e6}};
    // A driven volume moves the pressure; a driven pressure moves the volume: in the first
    // state the volume, after it the volume added since (what the states report).
    double relative = share(dp, c.multiplier());
    if (c.control() == Constraint::Control::multiplier) {
      if (rest_change.empty()) {
        relative = share(dV, c.measure());
      } else {
        const double dAdded = dV - rest_change[k];
        entry["added_volume_ml"] = dAdded * 1e6;
        relative = share(dAdded, c.measure() - c.rest_measure());
      }
    }
    entry["relative"] = relative;
    cavities.push_back(entry);
    if (relative > largest) {
      largest = relative;
      std::snprintf(text, sizeof text, "cavity '%s' by %.3g Pa and %.3g ml (%.2g %%)",
                    c.name().c_str(), dp, dV * 1e6, 100 * relative);
      worst = text;
    }
  }
  report["cavities"] = cavities;

  if (config.tip) {
    const TipOrientation a = tip_orientation(problem, config.tip->group, config.gravity, u);
    const TipOrientation b = tip_orientation(problem, config.tip->group, config.gravity, v);
    const auto &d = a.displacement, &e = b.displacement;
    const double moved = std::hypot(e[0] - d[0], e[1] - d[1], e[2] - d[2]);
    const double relative = share(moved, std::hypot(d[0], d[1], d[2]));
    report["tip"] = {{"displacement_m", {e[0] - d[0], e[1] - d[1], e[2] - d[2]}},
                     {"displacement_magnitude_m", moved},
                     {"inclination_deg", b.inclination_deg - a.inclination_deg},
                     {"rotation_deg", b.rotation_deg - a.rotation_deg},
                     {"relative", relative}};
    if (relative > largest) {
      largest = relative;
      std::snprintf(text, sizeof text, "the tip by %.3g mm (%.2g %%) and %.3g deg", moved * 1e3,
                    100 * relative, b.rotation_deg - a.rotation_deg);
      worst = text;
    }
  }
  report["warning"] = largest > kLoadModelWarning;
  if (largest > kLoadModelWarning && rank == 0)
    std::cerr << "hydrosoft: warning: state '" << state
              << "': the liquid's exact weight would move " << worst
              << ": the column method is off here (fluid_weight.method: hydrostatic is "
              << "exact; docs/cavities.md)" << std::endl;
  return error;
}

}  // namespace hs
