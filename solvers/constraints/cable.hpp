// A cable (tendon) actuator: its tension T is the multiplier, its measure the cable's length
// with a minus sign, q = -L(u), so that its forces g = -dL/du pull the path's points and a
// growing q (a shortening: the pull) is what a tension drives. The path's geometry is
// CablePath (cable_path.hpp); docs/control.md has the rest.
#pragma once

#include <memory>

#include "deck/config.hpp"
#include "solvers/constraints/cable_path.hpp"
#include "solvers/constraints/constraint_kinds.hpp"

namespace hs {

class Cable : public Constraint {
 public:
  // Collective; throws InputError naming the deck, the cable and a point outside the mesh.
  Cable(const CableConfig& config, ConstraintContext& context);

  std::string kind() const override { return "cable"; }
  bool actuated() const override { return true; }
  const char* family() const override { return "cables"; }
  Units units() const override { return {"N", "m"}; }
  double measure_at(Vec u) const override;
  void forces(Vec u, Vec g) const override;
  // Every dof of the points' elements: a straight path's inner points carry no force at rest.
  void mark_reads(Vec marks) const override;
  // Its tension acts on its points as a load: lambda g.
  bool adds_load() const override { return true; }
  void add_load(Vec u, double s, Vec load) override;
  void set_stiffness(Vec u, Problem& problem) override;
  nlohmann::json report() const override;
  // cable_<name>_force_N and _pull_m (the shortening since the end of the first state).
  void add_history(HistoryRow& row) const override;

 protected:
  Problem& problem_;
  CablePath path_;
  VecHandle pull_;  // g at the last load
};

}  // namespace hs
