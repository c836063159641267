#include "solvers/stepping.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "common/error.hpp"
#include "common/interrupt.hpp"

namespace hs {

std::vector<double> load_schedule(const TimeConfig& time) {
  if (!time.schedule.empty()) return time.schedule;
  std::vector<double> s(time.steps);
  for (int k = 0; k < time.steps; ++k) s[k] = static_cast<double>(k + 1) / time.steps;
  return s;
}

std::string format_time(double seconds) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.12g", seconds);
  return buffer;
}

std::string newton_failure(const NewtonResult& r) {
  std::ostringstream msg;
  msg << "Newton did not converge (" << r.reason << ", residual " << r.residual_norm << " after "
      << r.iterations << " iterations)";
  return msg.str();
}

void fail_step(const Problem& problem, int step, const std::string& where, const std::string& why) {
  std::string msg = "step " + std::to_string(step) + " (" + where + "): " + why;
  if (problem.inverted_element() >= 0)
    msg += "; element " + std::to_string(problem.inverted_element()) + " is inverted (det F <= 0)";
  if (problem.obstacle_reached() >= 0)
    msg += "; a node of the body reached obstacle '" +
           problem.contact()->obstacles()[problem.obstacle_reached()].name +
           "' (the contact barrier refuses it: smaller load steps or a larger contact.distance)";
  throw SolveError(msg);
}

namespace {

std::string g(double x) {
  std::ostringstream text;
  text << x;
  return text.str();
}

}  // namespace

static_assert(kMinIncrement == 0x1p-40, "the message names it");

int64_t max_substeps(int64_t planned) {
  return std::max(kMinSubstepsPerRun, kSubstepsPerPlannedStep * planned);
}

void advance_with_cutback(
    double from, double to, int max_cutbacks, SteppingStats& stats, MPI_Comm comm,
    const std::function<NewtonResult(double)>& attempt,
    const std::function<void(double, const NewtonResult&, const std::string&)>& give_up) {
  double done = 0, increment = 1;      // fractions of the way from `from` to `to`
  double at = from;                    // the parameter of the last converged state
  int64_t halvings = 0, failures = 0;  // in a row; in this step
  const int64_t max_failures = int64_t{kCutbacksPerStepPerMaxCutbacks} * max_cutbacks;
  auto parameter = [&](double fraction) { return from + fraction * (to - from); };
  for (bool first = true; done < 1; first = false) {
    // A step that goes on past its first solve asks before each further one whether a
    // signal came (a step done in one solve is asked at its end, as every step).
    if (!first) stop_if_interrupted(comm);
    const double next = std::min(1.0, done + increment);
    const double t = parameter(next);
    const NewtonResult r = attempt(t);
    stats.newton_iterations += r.iterations;
    stats.linear_iterations += r.linear_iterations;
    if (r.converged) {
      done = next;
      at = t;
      ++stats.steps;
      halvings = 0;
      increment = std::min(1.0, 2 * increment);
      if (done < 1 && stats.max_steps > 0 && stats.steps >= stats.max_steps)
        give_up(t, r,
                "the run has taken " + std::to_string(stats.steps) +
                    " converged sub-steps, the most it may (" +
                    std::to_string(kSubstepsPerPlannedStep) + " per planned step, at least " +
                    std::to_string(kMinSubstepsPerRun) + "): give it more steps");
      continue;
    }
    ++stats.cutbacks;
    if (++halvings > max_cutbacks)
      give_up(t, r,
              newton_failure(r) + " after " + std::to_string(max_cutbacks) +
                  " halvings of the increment in a row (time.max_cutbacks)");
    if (++failures > max_failures)
      give_up(t, r,
              newton_failure(r) + "; the step was cut back " + std::to_string(max_failures) +
                  " times, the most a step may (" + std::to_string(kCutbacksPerStepPerMaxCutbacks) +
                  " x time.max_cutbacks)");
    increment /= 2;
    if (increment < kMinIncrement)
      give_up(t, r,
              newton_failure(r) + " with an increment of " + g(2 * increment) +
                  " of the step; a smaller one is below the least a step takes (2^-40 of it)");
    // An increment that no longer changes the parameter would solve the converged state
    // again, converge, and start over.
    if (parameter(std::min(1.0, done + increment)) == at)
      give_up(t, r,
              newton_failure(r) + "; halving the increment again would leave " + g(at) +
                  " unchanged in floating point");
  }
}

}  // namespace hs
