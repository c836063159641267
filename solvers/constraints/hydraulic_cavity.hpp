// A hydraulic cavity: a pneumatic cavity full of liquid whose weight W(u) also loads the
// walls (the paper's Sections III-IV). The liquid's volume is the cavity's volume, so the
// weight follows the volume: dW = (W / V) g^T du. The weight is either recomputed on every
// configuration (coupling converged) or, as in the paper, frozen in shape at the start of a
// step and scaled with the volume, W = w V / v_c (coupling linearized: J_w = w / v_c).
// Weightless (density 0, or no gravity) it is a pneumatic cavity of kind hydraulic.
#pragma once

#include <array>
#include <memory>

#include "solvers/constraints/cavity.hpp"
#include "solvers/constraints/cavity_weight.hpp"

namespace hs {

class HydraulicCavity : public Cavity {
 public:
  HydraulicCavity(const CavityConfig& config, ConstraintContext& context);

  // Whether the liquid weighs anything (density > 0 under gravity).
  static bool weighs(const CavityConfig& config, const std::array<double, 3>& gravity);

  bool adds_load() const override { return weight_ != nullptr; }
  void add_load(Vec u, double s, Vec load) override;
  Vec measure_load() const override { return W_; }
  void freeze(Vec u, double s) override;
  bool frozen_coupling() const override { return frozen_ != nullptr; }
  // Frozen, the weights are w V / v_c within a step: smooth.
  double load_jump() const override { return weight_ && !frozen_ ? weight_->column_weight() : 0.0; }
  const FluidWeightUse* fluid_weight() const override { return weight_ ? &use_ : nullptr; }
  // A column method's weight against the closed form (the liquid's pressure on every wall).
  bool use_exact_load(bool on) override;
  nlohmann::json report() const override;

 private:
  std::unique_ptr<CavityWeight> weight_;  // liquid with density > 0 under gravity only
  std::unique_ptr<CavityWeight> exact_;   // the closed form, made for use_exact_load only
  VecHandle W_kept_;                      // W_ while the closed form is in its place
  bool exact_on_ = false;
  std::array<double, 3> gravity_{};
  VecHandle W_;       // its nodal weights (current)
  VecHandle frozen_;  // linearized: weights at the start of the step
  double frozen_volume_ = 0;
  FluidWeightUse use_;
};

}  // namespace hs
