#include "solvers/incompressibility.hpp"

#include <petscsys.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cstdio>
#include <deque>

#include "solvers/petsc_check.hpp"

namespace hs {
namespace {

// Anderson's mixing of the raises (type II, the last kAndersonDepth differences): the raise
// lambda -> lambda + kbar M(lambda) contracts the volume change by only about 5 a raise on
// a nodal-pressure body (its pressure pair is not inf-sup stable: a few patch modes are held
// weakly), and mixing the last raises takes out those modes' slow part.
constexpr size_t kAndersonDepth = 3;

std::vector<double> mixed_multipliers(const Problem& problem,
                                      const std::deque<std::vector<double>>& lambda,
                                      const std::deque<std::vector<double>>& raise) {
  const size_t m = lambda.size() - 1, n = lambda.back().size();
  std::vector<double> next(n);
  for (size_t k = 0; k < n; ++k) next[k] = lambda.back()[k] + raise.back()[k];
  if (m == 0) return next;
  std::vector<std::vector<double>> dF(m, std::vector<double>(n));
  for (size_t i = 0; i < m; ++i)
    for (size_t k = 0; k < n; ++k) dF[i][k] = raise[i + 1][k] - raise[i][k];
  Eigen::MatrixXd A(m, m);
  Eigen::VectorXd b(m);
  for (size_t i = 0; i < m; ++i) {
    b(i) = problem.multiplier_dot(dF[i], raise.back());
    for (size_t j = 0; j <= i; ++j) A(i, j) = A(j, i) = problem.multiplier_dot(dF[i], dF[j]);
  }
  const Eigen::VectorXd gamma = A.completeOrthogonalDecomposition().solve(b);
  for (size_t i = 0; i < m; ++i)
    for (size_t k = 0; k < n; ++k)
      next[k] -= gamma(i) * (lambda[i + 1][k] - lambda[i][k] + dF[i][k]);
  return next;
}

}  // namespace

NewtonResult solve_keeping_volumes(Problem& problem, Vec u,
                                   const std::function<NewtonResult()>& solve, bool monitor) {
  if (!problem.has_volume_multipliers()) return solve();
  const std::vector<double> start = problem.volume_multipliers();
  std::deque<std::vector<double>> lambda, raise;
  NewtonResult total;
  double previous_change = 0;
  double penalty = kFbarPenaltyStart;
  problem.scale_fbar_penalty(penalty);
  for (int raises = 0;; ++raises) {
    const NewtonResult r = solve();
    total.iterations += r.iterations;
    total.linear_iterations += r.linear_iterations;
    total.residual_norm = r.residual_norm;
    total.reason = r.reason;
    if (!r.converged) break;
    const double change = problem.largest_volume_change(u);
    if (monitor)
      HS_PETSC(
          PetscPrintf(problem.comm(),
                      "  volume multipliers: %d raises, |ln J| <= %.3e (%d Newton iterations)\n",
                      raises, change, r.iterations));
    if (change <= kVolumeTolerance) {
      problem.scale_fbar_penalty(1);
      problem.record_volumes_kept(change, raises);
      total.converged = true;
      return total;
    }
    if (raises == kMaxMultiplierRaises) {
      char why[160];
      std::snprintf(why, sizeof why,
                    "DIVERGED_VOLUME_MULTIPLIERS (a patch's volume still changes by %.3g after "
                    "%d raises of its multiplier)",
                    change, raises);
      total.reason = why;
      break;
    }
    if (raises > 0 && change > previous_change) {  // the mixing went astray: start it again
      lambda.clear();
      raise.clear();
    }
    const bool slow_raise = raises > 0 && change > kSlowRaise * previous_change;
    previous_change = change;
    lambda.push_back(problem.volume_multipliers());
    raise.push_back(problem.volume_multiplier_raise());
    if (lambda.size() > kAndersonDepth + 1) {
      lambda.pop_front();
      raise.pop_front();
    }
    const std::vector<double> next = mixed_multipliers(problem, lambda, raise);
    if (slow_raise && penalty < 1) {  // the raise after it is made with the new one
      penalty = std::min(kPenaltyGrowth * penalty, 1.0);
      problem.scale_fbar_penalty(penalty);
      lambda.clear();
      raise.clear();
    }
    problem.set_volume_multipliers(next);
  }
  problem.set_volume_multipliers(start);
  problem.scale_fbar_penalty(1);
  return total;
}

}  // namespace hs
