// One scalar constraint of equation (1) of the paper: a multiplier lambda (a cavity's gauge
// pressure, a cable's tension) whose forces on the body are lambda g(u), and a measure q(u)
// of the body (a cavity's volume, a cable's length with a minus sign, so that g = dq/du for a
// frictionless actuator and a growing q is what the multiplier pushes towards). The residual
// of the body becomes
//   R(u, lambda) = f_int(u) - s f_body - sum_k lambda_k g_k(u) - sum_k w_k(u)
// (w_k: loads a constraint adds of its own, e.g. a liquid's weight), and each constraint
// brings one equation more, its control c_k(u, lambda_k) = 0:
//   multiplier  lambda - target                   (a prescribed pressure or tension)
//   measure     q(u) - target                     (a prescribed volume)
//   own law     the kind's own equation           (a sealed chamber: p V = const, V = V_0)
// linearised as alpha g^T du + b dlambda. ConstraintSet (constraint_set.hpp) holds the
// constraints of a scene and assembles these terms; BorderedNewton solves them; the inverse
// controller drives the actuated ones. docs/architecture.md, "How to add a constraint".
#pragma once

#include <petscvec.h>

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "solvers/petsc_handle.hpp"

namespace hs {

class Problem;

class Constraint {
 public:
  enum class Control { multiplier, measure, own_law };

  explicit Constraint(std::string name) : name_(std::move(name)) {}
  virtual ~Constraint() = default;
  Constraint(const Constraint&) = delete;
  Constraint& operator=(const Constraint&) = delete;

  // Its name in the deck (a cavity's group, a cable's name) and kind (summary.json's "kind").
  const std::string& name() const { return name_; }
  virtual std::string kind() const = 0;
  // Whether states and the controller may drive it (pneumatic, hydraulic, cable).
  virtual bool actuated() const = 0;
  // Whether it is a cavity: cavities count in a state's added volume and in parts.cavities.
  virtual bool is_cavity() const = 0;

  // q(u), collective.
  virtual double measure_at(Vec u) const = 0;
  // The forces of a unit multiplier (J^T), Dirichlet rows zero; for a frictionless actuator
  // g = dq/du. Collective.
  virtual void forces(Vec u, Vec g) const = 0;
  // Puts lambda's forces where the residual finds them: a cavity's walls carry it as a
  // follower pressure of the problem. Called before every residual.
  virtual void apply_multiplier(Problem&) {}
  // Whether add_load adds anything.
  virtual bool adds_load() const { return false; }
  // Adds the loads it contributes itself at (u, s) to `load` (a cable: lambda g; a liquid:
  // its weight). Called after measure is updated, before every residual.
  virtual void add_load(Vec /*u*/, double /*s*/, Vec /*load*/) {}
  // Sets the stiffness of its forces that the element tangent does not hold (a cable's
  // turning tension), before every tangent.
  virtual void set_stiffness(Vec /*u*/, Problem&) {}
  // Whether the stiffness it adds keeps the tangent symmetric (forces that are a gradient).
  virtual bool symmetric_stiffness() const { return true; }
  // q's own loads that follow q (a liquid's weight w, dw = (w / q) g^T du): w, else nullptr.
  virtual Vec measure_load() const { return nullptr; }
  // Linearized weight coupling: freezes the distribution of its load at u.
  virtual void freeze(Vec /*u*/, double /*s*/) {}
  virtual bool frozen_coupling() const { return false; }

  // The control equation's value, linearisation and scale (for convergence tests).
  double control_residual() const;
  void control_linearization(double& alpha, double& b) const;
  double control_scale() const;

  // What summary.json reports of it now.
  virtual nlohmann::json report() const = 0;
  // Why its state is outside the domain (a cavity's volume <= 0), else "".
  virtual std::string collapse_reason() const { return ""; }

  // The bordered Newton's state of this constraint, shared by every kind.
  double lambda = 0;  // multiplier: Pa or N
  double target = 0;  // prescribed multiplier or measure of the current increment
  Control control = Control::multiplier;
  double measure = 0;            // q at the last evaluation
  double reference_measure = 0;  // on the undeformed mesh
  double rest_measure = 0;       // at the end of the first state
  // What the first state ramps from 0 to full: the multiplier, or the measure's change.
  double first_state_multiplier = 0;
  std::optional<double> first_state_measure_change;

 protected:
  // own_law: c, its linearisation and scale.
  virtual double law_residual() const { return 0; }
  virtual void law_linearization(double& /*alpha*/, double& /*b*/) const {}
  virtual double law_scale() const { return 1; }

 private:
  std::string name_;
};

}  // namespace hs
