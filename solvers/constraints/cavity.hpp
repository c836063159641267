// A cavity: a closed surface of the mesh (the boundary faces of a surface group, pointing out
// of the body into the cavity) filled with gas or liquid at a uniform gauge pressure lambda.
// Its measure is the enclosed volume V(u), its forces g = dV/du the follower pressure on its
// walls (the paper's J_p^T, Section IV). This class is the pneumatic cavity, driven by its
// pressure or by its added volume (then the pressure is an unknown); the hydraulic and the
// sealed cavities build on it. docs/cavities.md derives the terms.
#pragma once

#include "deck/config.hpp"
#include "solvers/constraints/constraint_kinds.hpp"

namespace hs {

class Mesh;

class Cavity : public Constraint {
 public:
  // Collective. Refuses (InputError naming the deck and the cavity) a surface that is not
  // closed, manifold and consistently oriented, one that encloses no positive volume, and an
  // added volume that would leave none.
  Cavity(const CavityConfig& config, ConstraintContext& context);

  std::string kind() const override { return name_of(kCavityKindNames, config_.kind); }
  bool actuated() const override { return is_actuated(config_.kind); }
  const char* family() const override { return "cavities"; }
  Units units() const override { return {"Pa", "m3"}; }
  double measure_at(Vec u) const override;
  void forces(Vec u, Vec g) const override;
  void apply_multiplier(Problem& problem) override;
  nlohmann::json report() const override;
  // cavity_<name>_pressure_Pa, _volume_m3, _added_volume_m3 (since the end of the first
  // state) and, with a liquid's weight, _fluid_weight_N.
  void add_history(HistoryRow& row) const override;
  std::string collapse_reason() const override;
  std::string ramp_failure_note() const override;

 protected:
  const CavityConfig& config() const { return config_; }
  Problem& problem_;

 private:
  CavityConfig config_;
  int surface_ = -1;  // the problem's pressure surface of its walls
};

}  // namespace hs
