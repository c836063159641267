// The constraints of a scene (constraint.hpp: cavities, cables) and what they add to
// equation (1) of the paper, for the bordered Newton (bordered_newton.hpp) and the inverse
// controller: the residual with every constraint's forces and loads, the controls c_k, and
// the tangent with the columns g_k and, where a constraint's own load follows its measure
// (a liquid's weight), q_k = w_k / q_k. Cavities come first, in the deck's order, then cables.
#pragma once

#include <petscmat.h>
#include <petscvec.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "deck/config.hpp"
#include "io/step_history.hpp"
#include "mesh/distribution.hpp"
#include "mesh/mesh.hpp"
#include "solvers/constraints/constraint.hpp"
#include "solvers/problem.hpp"

namespace hs {

// The linear algebra of one Newton step: the tangent J (with -lambda H), the columns g_k and
// q_k (nullptr where a constraint has no load following its measure), and the controls'
// linearisation alpha_k g_k^T du + b_k dlambda_k.
struct ConstraintLinearization {
  VecArray g, q;
  std::vector<double> alpha, b;
};

class ConstraintSet {
 public:
  // Collective. Makes the deck's cavities and cables (InputError for a bad one).
  ConstraintSet(const Config& config, Problem& problem);
  ~ConstraintSet();
  ConstraintSet(const ConstraintSet&) = delete;
  ConstraintSet& operator=(const ConstraintSet&) = delete;

  int size() const { return static_cast<int>(constraints_.size()); }
  Constraint& operator[](int k) { return *constraints_[k]; }
  const Constraint& operator[](int k) const { return *constraints_[k]; }
  // The index of the constraint of that name, or -1.
  int find(const std::string& name) const;
  std::vector<double> multipliers() const;
  void set_multipliers(const std::vector<double>& lambda);
  // Every constraint's state, and the same put back.
  std::vector<Constraint::State> snapshot() const;
  void restore(const std::vector<Constraint::State>& states);
  // A point of the equations to come back to after residuals elsewhere: every constraint's
  // state and the own loads (a liquid's weight) as the last residual left them. Put back, the
  // multipliers are also where the residual finds them (a cavity's pressure on its walls).
  struct Point {
    std::vector<Constraint::State> states;
    VecHandle loads;
  };
  Point point() const;
  void return_to(const Point& point);

  // R(u, lambda; s) and the controls c (size()). Returns false on an inverted element or a
  // constraint outside its domain (collapse_reason() then says why).
  bool residual(Vec u, double s, Vec R, std::vector<double>& c);
  // The forces the constraints exert on the body at (u, lambda; s), with the sign of a load:
  // their multipliers' (a cavity's pressure on its walls, a cable's tension) and their own
  // loads (a liquid's weight), the part of R(u, lambda; s) they are; the measures updated. A
  // reduced model evaluates them apart from the elements. False when a constraint left its
  // domain (collapse_reason()).
  bool loads(Vec u, double s, Vec f);
  // What loads() computes besides the multipliers' forces: the measures and each
  // constraint's own load (its measure_load()) at (u, s). loads() is then sum_c lambda_c
  // times the forces of constraint c (its forces(), where the Dirichlet rows are not zeroed)
  // plus the measure loads, which a reduced model assembles from the unit forces it needs
  // anyway. False when a constraint left its domain.
  bool measure(Vec u, double s) { return update(u, s); }
  // After a residual() that returned false: why, if a constraint left its domain; else "".
  std::string collapse_reason() const;
  // The largest load_jump() of its constraints (N).
  double load_jump() const;
  // Tangent and linearisation at (u, lambda; s), after a residual() at the same point.
  bool linearize(Vec u, double s, Mat J, ConstraintLinearization& lin);
  // q_k(u) (collective).
  double measure(int k, Vec u) const { return constraints_[k]->measure_at(u); }
  double control_scale(int k) const { return constraints_[k]->control_scale(); }

  // Whether every constraint keeps the tangent symmetric.
  bool symmetric() const;
  // Whether every constraint is a cavity whose pressure is prescribed and that adds no load of
  // its own (no liquid's weight): Newton's steps then leave the pressures as they are, and the
  // residual is the gradient of Problem::potential_energy.
  bool holds_pressures() const;
  // Linearized coupling: freezes each hydraulic cavity's weights at configuration u.
  void freeze_weights(Vec u, double s);
  bool linearized() const { return linearized_; }

  // The liquids' weights of the hydraulic cavities, as the last residual added them, into f
  // (assembled); false, f untouched, when no cavity's liquid weighs anything.
  bool fluid_weight_load(Vec f) const;

  // Fluid-weight seconds and calls so far, and what ran (for summary.json).
  double fluid_weight_seconds() const;
  int fluid_weight_calls() const;
  // Seconds spent building the constraints: measures, their forces g, the columns q, the
  // cables' stiffness (not the FEM assembly).
  double constraint_build_seconds() const { return build_seconds_; }
  nlohmann::json parts() const;
  // Collective: summary.json's {"cavities": [...], "cables": [...]}, an entry per constraint
  // in the list of its family.
  nlohmann::json report() const;
  // Collective: each constraint's columns of the history now (docs/output.md).
  void add_history(HistoryRow& row) const;
  // The volume the constraints that measure one (the cavities) gained since the end of the
  // first state, and since the undeformed mesh: m^3.
  double added_volume() const;
  double volume_change() const;

 private:
  // Before the constraints' forces are read at (u, s): each multiplier put where the residual
  // finds it, the measures, the own loads; false when a constraint left its domain.
  bool update(Vec u, double s);
  Problem& problem_;
  std::vector<std::unique_ptr<Constraint>> constraints_;
  VecHandle loads_;  // the constraints' own loads, the problem's extra load
  bool linearized_ = false;
  int collapsed_ = -1;  // the first constraint outside its domain at the last residual(), or -1
  double build_seconds_ = 0;
};

// Whether its measure is a volume (a cavity's), which states add up.
bool measures_volume(const Constraint& c);

}  // namespace hs
