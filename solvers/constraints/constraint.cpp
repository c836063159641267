#include "solvers/constraints/constraint.hpp"

#include <algorithm>
#include <cmath>

namespace hs {

double Constraint::control_residual() const {
  switch (state_.control) {
    case Control::multiplier:
      return state_.multiplier - state_.target;
    case Control::measure:
      return state_.measure - state_.target;
    case Control::own_law:
      return law_residual();
  }
  return 0;
}

void Constraint::control_linearization(double& alpha, double& b) const {
  alpha = b = 0;
  switch (state_.control) {
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
  switch (state_.control) {
    case Control::multiplier:
      return std::max(std::abs(state_.target), 1.0);
    case Control::measure:
      return reference_measure_;
    case Control::own_law:
      return law_scale();
  }
  return 1;
}

void Constraint::prescribe(Control control, double target) {
  state_.control = control;
  state_.target = target;
  if (control == Control::multiplier) state_.multiplier = target;
}

double Constraint::first_state_target(double tau) const {
  switch (state_.control) {
    case Control::multiplier:
      return tau * first_state_multiplier_;
    case Control::measure:
      return reference_measure_ + tau * first_state_measure_change_.value_or(0.0);
    case Control::own_law:
      break;
  }
  return state_.target;
}

void Constraint::set_reference_measure(double q) {
  reference_measure_ = state_.measure = state_.rest_measure = q;
}

void Constraint::set_first_state(double multiplier, std::optional<double> measure_change) {
  first_state_multiplier_ = multiplier;
  first_state_measure_change_ = measure_change;
  state_.control = measure_change ? Control::measure : Control::multiplier;
}

}  // namespace hs
