#include "solvers/constraints/constraint.hpp"

#include <algorithm>
#include <cmath>

namespace hs {

double Constraint::control_residual() const {
  switch (control) {
    case Control::multiplier:
      return lambda - target;
    case Control::measure:
      return measure - target;
    case Control::own_law:
      return law_residual();
  }
  return 0;
}

void Constraint::control_linearization(double& alpha, double& b) const {
  alpha = b = 0;
  switch (control) {
    case Control::multiplier:
      b = 1;
      break;
    case Control::measure:
      alpha = 1;
      break;
    case Control::own_law:
      law_linearization(alpha, b);
      break;
  }
}

double Constraint::control_scale() const {
  switch (control) {
    case Control::multiplier:
      return std::max(std::abs(target), 1.0);
    case Control::measure:
      return reference_measure;
    case Control::own_law:
      return law_scale();
  }
  return 1;
}

}  // namespace hs
