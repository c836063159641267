#include "solvers/tip_orientation.hpp"

#include <cmath>

#include "solvers/petsc_check.hpp"

namespace hs {
namespace {

constexpr double kPi = 3.14159265358979323846;

double angle_deg(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  const double cross =
      std::hypot(a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]);
  return std::atan2(cross, a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) * 180 / kPi;
}

}  // namespace

TipOrientation tip_orientation(Problem& problem, const std::string& group,
                               const std::array<double, 3>& gravity, Vec u) {
  TipOrientation t;
  const auto n = problem.area_vector(group, u);
  VecHandle zero;
  HS_PETSC(VecDuplicate(u, zero.out()));
  HS_PETSC(VecZeroEntries(zero));
  const auto n0 = problem.area_vector(group, zero);
  t.rotation_deg = angle_deg(n0, n);
  // The angle to gravity is 90 deg minus the inclination below the plane normal to it.
  if (std::hypot(gravity[0], gravity[1], gravity[2]) > 0 && std::hypot(n[0], n[1], n[2]) > 0)
    t.inclination_deg = 90 - angle_deg(n, gravity);
  t.displacement = problem.mean_displacement(group, u);
  return t;
}

}  // namespace hs
