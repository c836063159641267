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
  if (frozen_) {  // the paper's J_w: the frozen distribution times V / v_c
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

nlohmann::json HydraulicCavity::report() const {
  nlohmann::json j = Cavity::report();
  if (weight_) j["fluid_weight_volume"] = weight_->measured_volume();
  return j;
}

}  // namespace hs
