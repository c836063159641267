#include "solvers/constraints/hydraulic_cavity.hpp"

#include <cmath>

#include "solvers/problem.hpp"

namespace hs {

bool HydraulicCavity::weighs(const CavityConfig& config, const std::array<double, 3>& gravity) {
  return config.density > 0 && std::hypot(gravity[0], gravity[1], gravity[2]) > 0;
}

HydraulicCavity::HydraulicCavity(const CavityConfig& config, ConstraintContext& context)
    : Cavity(config, context) {
  const std::array<double, 3>& gravity = context.config.gravity;
  gravity_ = gravity;
  if (!weighs(config, gravity)) return;
  weight_ = std::make_unique<CavityWeight>(context.problem.distribution(), config, gravity,
                                           context.next_weighing_rank(), context.problem.comm());
  use_.device = weight_->device();
  use_.method = name_of(kWeightMethodNames, config.fluid_weight.method);
  W_ = VecHandle(context.problem.create_vector());
  if (config.fluid_weight.coupling == WeightCoupling::linearized)
    frozen_ = VecHandle(context.problem.create_vector());
}

void HydraulicCavity::add_load(Vec u, double s, Vec load) {
  if (!weight_) return;
  if (exact_on_) {
    HS_PETSC(VecSet(W_, 0.0));
    exact_->add_weight(u, s, W_);
  } else if (frozen_) {  // the paper's J_w: the frozen distribution times V / v_c
    HS_PETSC(VecAXPBY(W_, measure() / frozen_volume_, 0.0, frozen_));
  } else {
    HS_PETSC(VecSet(W_, 0.0));
    weight_->add_weight(u, s, W_);
    use_.seconds += weight_->seconds();
    ++use_.calls;
  }
  HS_PETSC(VecAXPY(load, 1.0, W_));
}

void HydraulicCavity::freeze(Vec u, double s) {
  if (!frozen_) return;
  HS_PETSC(VecSet(frozen_, 0.0));
  weight_->add_weight(u, s, frozen_);
  use_.seconds += weight_->seconds();
  ++use_.calls;
  frozen_volume_ = measure_at(u);
}

bool HydraulicCavity::use_exact_load(bool on) {
  if (!weight_ || config().fluid_weight.method == WeightMethod::hydrostatic) return false;
  if (on == exact_on_) return true;
  if (!exact_) {
    CavityConfig closed_form = config();
    closed_form.fluid_weight.method = WeightMethod::hydrostatic;
    closed_form.fluid_weight.device = WeightDevice::cpu;
    exact_ = std::make_unique<CavityWeight>(problem_.distribution(), closed_form, gravity_,
                                            weight_->owner(), problem_.comm());
    W_kept_ = VecHandle(problem_.create_vector());
  }
  // The weights as the last residual left them come back with the approximation: what is
  // reported of the state is the run's own.
  HS_PETSC(VecCopy(on ? W_.get() : W_kept_.get(), on ? W_kept_.get() : W_.get()));
  exact_on_ = on;
  return true;
}

nlohmann::json HydraulicCavity::report() const {
  nlohmann::json j = Cavity::report();
  if (weight_) j["fluid_weight_volume"] = weight_->measured_volume();
  return j;
}

}  // namespace hs
