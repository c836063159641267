// The measures an exact solution asks for (src/verification/exact_solution.hpp), taken on the
// computed displacement, and its verification quantities made of them.
#include <cmath>

#include "solvers/verification/error_norms.hpp"

namespace hs {
namespace {

double measure(const MeasureRequest& request, Problem& problem, Vec u) {
  switch (request.measure) {
    case Measure::mean_displacement_z: {
      const double count =
          problem.sum_over_group(request.group, u, [](auto&, auto&) { return 1.0; });
      const double sum =
          problem.sum_over_group(request.group, u, [](auto&, auto& v) { return v[2]; });
      return sum / count;
    }
    case Measure::radial_reaction: {
      // At constrained nodes the internal forces are the reactions.
      VecHandle f;
      HS_PETSC(VecDuplicate(u, f.out()));
      problem.internal_force(u, f);
      const double radial = problem.sum_over_group(request.group, f, [](auto& X, auto& v) {
        const double R = std::sqrt(X[0] * X[0] + X[1] * X[1] + X[2] * X[2]);
        return (v[0] * X[0] + v[1] * X[1] + v[2] * X[2]) / R;
      });
      return radial;
    }
  }
  return 0;
}

}  // namespace

nlohmann::json verification_quantities(const ExactSolution& exact, Problem& problem, Vec u,
                                       double s) {
  const auto requests = exact.measures();
  if (requests.empty()) return nullptr;
  std::vector<double> measured;
  for (const auto& request : requests) measured.push_back(measure(request, problem, u));
  return exact.verification(measured, s);
}

}  // namespace hs
