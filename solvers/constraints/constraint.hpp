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
// linearised as alpha g^T du + b dlambda. A constraint owns its state (State: what the
// bordered Newton and the controller change, what a checkpoint keeps) and says how it is
// reported (its family in summary.json, its units, its history columns); the kinds are
// made from the deck by constraint_kinds.cpp. ConstraintSet (constraint_set.hpp) holds the
// constraints of a scene and assembles these terms; BorderedNewton solves them; the inverse
// controller drives the actuated ones. docs/architecture.md, "How to add a constraint".
#pragma once

#include <petscvec.h>

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "io/step_history.hpp"
#include "solvers/petsc_handle.hpp"

namespace hs {

class Problem;

// What the fluid-weight module did for a constraint whose liquid weighs something.
struct FluidWeightUse {
  double seconds = 0;
  int calls = 0;
  std::string device;  // "cpu" or "cuda"
  std::string method;  // the deck's fluid_weight.method
};

class Constraint {
 public:
  enum class Control { multiplier, measure, own_law };

  // The state that Newton, the stepping and the controller change and a checkpoint keeps.
  struct State {
    double multiplier = 0;  // lambda: Pa or N
    double target = 0;      // of the control, at the current increment
    Control control = Control::multiplier;
    double measure = 0;       // q at the last evaluation
    double rest_measure = 0;  // q at the end of the first state
  };

  // The units of the multiplier and of the measure, as the history's column names write them.
  struct Units {
    const char* multiplier;  // "Pa", "N"
    const char* measure;     // "m3", "m"
  };

  explicit Constraint(std::string name) : name_(std::move(name)) {}
  virtual ~Constraint() = default;
  Constraint(const Constraint&) = delete;
  Constraint& operator=(const Constraint&) = delete;

  // Its name in the deck (a cavity's group, a cable's name) and kind (summary.json's "kind").
  const std::string& name() const { return name_; }
  virtual std::string kind() const = 0;
  // The list of summary.json it is reported in ("cavities", "cables").
  virtual const char* family() const = 0;
  virtual Units units() const = 0;
  // Whether states and the controller may drive it (pneumatic, hydraulic, cable).
  virtual bool actuated() const = 0;

  // q(u), collective.
  virtual double measure_at(Vec u) const = 0;
  // The forces of a unit multiplier (J^T), Dirichlet rows zero; for a frictionless actuator
  // g = dq/du. Collective.
  virtual void forces(Vec u, Vec g) const = 0;
  // Sets to 1 in `marks` the dofs whose displacement q and g read, where g at rest can be
  // zero on some of them (a reduced model keeps exactly these up to date). The default marks
  // none: a cavity's unit forces at rest act on every wall node. Collective.
  virtual void mark_reads(Vec /*marks*/) const {}
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
  // How far its loads can jump between two configurations as close as one likes (N): a
  // column method's weights move by up to one column's weight when a wall crosses a column's
  // centre. Newton's residual cannot be asked to fall below it. 0 for loads smooth in u.
  virtual double load_jump() const { return 0; }
  // The fluid-weight module's work for it, or nullptr where no liquid weighs.
  virtual const FluidWeightUse* fluid_weight() const { return nullptr; }
  // Where its own load is an approximation (a liquid's weight by the column method): puts the
  // exact load in its place (on) or the approximation back (off), for the estimate of the
  // approximation's error (solvers/stepping/load_model_error.hpp). Collective. False where its
  // load is exact already, or it has none.
  virtual bool use_exact_load(bool /*on*/) { return false; }

  // The control equation's value, linearisation and scale (for convergence tests).
  double control_residual() const;
  void control_linearization(double& alpha, double& b) const;
  double control_scale() const;

  // Its state.
  double multiplier() const { return state_.multiplier; }
  double measure() const { return state_.measure; }
  double target() const { return state_.target; }
  Control control() const { return state_.control; }
  double rest_measure() const { return state_.rest_measure; }
  double reference_measure() const { return reference_measure_; }
  void set_multiplier(double lambda) { state_.multiplier = lambda; }
  // Drives it by `control` towards `target`; a prescribed multiplier is also set.
  void prescribe(Control control, double target);
  // The target of its present control (a prescribed multiplier is also set).
  void set_target(double target) { prescribe(state_.control, target); }
  // Holds the multiplier where it is: the controller's actuators between its steps.
  void hold_multiplier() { prescribe(Control::multiplier, state_.multiplier); }
  // q at u, kept as its measure (collective).
  void update_measure(Vec u) { state_.measure = measure_at(u); }
  // The end of the first state: added volumes and pulls count from the measure now.
  void mark_rest() { state_.rest_measure = state_.measure; }
  State snapshot() const { return state_; }
  void restore(const State& state) { state_ = state; }

  // The first state ramps what the deck sets from nothing (tau = 0) to all of it (tau = 1):
  // its control's target at tau.
  virtual double first_state_target(double tau) const;
  // Whether the first state ramps anything of its own.
  bool ramped_in_first_state() const {
    return first_state_multiplier_ != 0 || first_state_measure_change_.value_or(0) != 0;
  }
  // Why no equilibrium may lie ahead on a ramp of its control (a pressure past a peak), or "".
  virtual std::string ramp_failure_note() const { return ""; }

  // What summary.json reports of it now (collective).
  virtual nlohmann::json report() const = 0;
  // Its columns of history.csv now (collective; docs/output.md).
  virtual void add_history(HistoryRow& row) const = 0;
  // Why its state is outside the domain (a cavity's volume <= 0), else "".
  virtual std::string collapse_reason() const { return ""; }

 protected:
  // At construction: q on the undeformed mesh (also its measure and rest measure), and what
  // the first state ramps: a multiplier, or a change of the measure.
  void set_reference_measure(double q);
  void set_first_state(double multiplier, std::optional<double> measure_change);
  // own_law: c, its linearisation and scale.
  virtual double law_residual() const { return 0; }
  virtual void law_linearization(double& /*alpha*/, double& /*b*/) const {}
  virtual double law_scale() const { return 1; }

 private:
  std::string name_;
  State state_;
  double reference_measure_ = 0;
  double first_state_multiplier_ = 0;
  std::optional<double> first_state_measure_change_;
};

}  // namespace hs
