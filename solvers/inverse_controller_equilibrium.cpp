// InverseController, the equilibria it stands on: the rest state, the free configuration
// converged by Newton (walking the pressures where Newton alone does not reach it), and the
// equilibrium at an actuation for the one_step mode's check.
#include <algorithm>

#include "common/error.hpp"
#include "solvers/inverse_controller.hpp"
#include "solvers/stepping.hpp"

namespace hs {

void InverseController::set_rest(Vec u) {
  for (auto& a : actuators_) a.rest_measure = constraints_.measure(a.constraint, u);
  if (!last_free_) HS_PETSC(VecDuplicate(u, last_free_.out()));
  HS_PETSC(VecCopy(u, last_free_));
  last_pressures_ = constraints_.multipliers();
  last_moves_ = problem_.boundary_moves();
}

// Newton from the corrected configuration: one linearisation away from equilibrium, it
// nearly always converges at once. Where it does not (a large pressure change on a wall that
// softens, near a limit point of the pressure), the pressures are walked from the last free
// equilibrium to the new ones with the halving increments of the load stepping; past a limit
// point no equilibrium exists, and the actuation stops at the last one reached. Boundary
// groups that a target set moves walk with the pressures, from their translations there.
NewtonResult InverseController::solve_free(Vec u, ControlStepReport& report) {
  const auto solve = [&](Vec x) {
    problem_.apply_dirichlet(x, 1.0);
    if (constraints_.linearized()) constraints_.freeze_weights(x, 1.0);
    const NewtonResult r = newton_.solve(x, 1.0);
    report.newton_iterations += r.iterations;
    return r;
  };
  const std::vector<double> wanted = constraints_.multipliers();
  const DofMap::Moves moved = problem_.boundary_moves();
  auto keep = [&]() {
    HS_PETSC(VecCopy(u, last_free_));
    last_pressures_ = constraints_.multipliers();
    last_moves_ = problem_.boundary_moves();
  };
  NewtonResult result = solve(u);
  if (result.converged || !last_free_) {
    if (result.converged) keep();
    return result;
  }
  HS_PETSC(VecCopy(last_free_, u));
  constraints_.set_multipliers(last_pressures_);
  const std::vector<double> from = last_pressures_;
  DofMap::Moves moved_from = last_moves_;
  moved_from.resize(moved.size(), {0, 0, 0});
  auto set_actuation = [&](double t) {
    for (const auto& a : actuators_) {
      const int c = a.constraint;
      constraints_[c].prescribe(Constraint::Control::multiplier,
                                from[c] + t * (wanted[c] - from[c]));
    }
    DofMap::Moves at = moved;
    for (size_t g = 0; g < at.size(); ++g)
      for (int d = 0; d < 3; ++d)
        at[g][d] = moved_from[g][d] + t * (moved[g][d] - moved_from[g][d]);
    problem_.set_boundary_moves(at);
  };
  struct Stop {};
  SteppingStats stats;
  auto attempt = [&](double t) {
    const std::vector<Constraint::State> before = constraints_.snapshot();
    set_actuation(t);
    const NewtonResult r = solve(u);
    if (r.converged) {
      keep();
    } else {
      HS_PETSC(VecCopy(last_free_, u));
      constraints_.restore(before);
    }
    result = r;
    return r;
  };
  try {
    advance_with_cutback(0.0, 1.0, config_.time.max_cutbacks, stats, problem_.comm(), attempt,
                         [](double, const NewtonResult&, const std::string&) { throw Stop{}; });
  } catch (const Stop&) {
    // Held at the last equilibrium reached on the way: a bound of physics, not of the deck.
    HS_PETSC(VecCopy(last_free_, u));
    constraints_.set_multipliers(last_pressures_);
    problem_.set_boundary_moves(last_moves_);
    for (const auto& a : actuators_) constraints_[a.constraint].hold_multiplier();
    result.converged = true;
    report.limit_point = true;
  }
  return result;
}

void InverseController::settle(Vec u, ControlStepReport& report) {
  for (const auto& a : actuators_) constraints_[a.constraint].hold_multiplier();
  const NewtonResult r = solve_free(u, report);
  if (!r.converged)
    throw SolveError("control: the equilibrium at the final actuation did not converge (" +
                     r.reason + ")");
  report.reached = effectors_.positions(u);
  report.actuation.clear();
  for (const auto& a : actuators_)
    report.actuation.push_back(constraints_[a.constraint].multiplier());
}

// On a copy, by the free solve: Newton from the prediction, or, where a kept factorization
// left the prediction too far off for Newton (a few steps of 5 kPa on the hydraulic finger),
// the pressures walked from the last equilibrium found here (or the rest state).
std::vector<double> InverseController::equilibrium_positions(Vec u) {
  // The controller's state is the one at u: what the check changes is put back.
  const std::vector<Constraint::State> at_u = constraints_.snapshot();
  Problem::TangentMemory tangent_at_u = problem_.tangent_memory();
  VecHandle x;
  HS_PETSC(VecDuplicate(u, x.out()));
  HS_PETSC(VecCopy(u, x));
  for (const auto& a : actuators_) constraints_[a.constraint].hold_multiplier();
  ControlStepReport report;
  const NewtonResult r = solve_free(x, report);
  const std::vector<double> positions = effectors_.positions(x);
  x.reset();
  constraints_.restore(at_u);
  problem_.restore_tangent_memory(std::move(tangent_at_u));
  if (!r.converged || report.limit_point)
    throw SolveError(
        "control: the equilibrium check found no equilibrium at the current "
        "actuation (" +
        (report.limit_point ? std::string("a limit point of the pressure on the way") : r.reason) +
        ")");
  return positions;
}

}  // namespace hs
