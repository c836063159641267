// Implicit dynamics of a scene with cavities and cables (Newmark, backward Euler): the deck's
// states become a schedule in time (docs/decks.md, "Dynamic runs with cavities and cables").
// Each state's values (the first state's load factor and the cavities' and cables' own
// controls, a later state's cavity targets) are reached at the time step of its `time`,
// ramped linearly from the previous state's, and held after the last state. Every time step
// is one solve of the bordered Newton (displacements and multipliers) with the inertia term
// c M (u - u_pred) in the residual and the tangent (a step whose solve fails is taken again
// in 2, 4, ... sub-steps, up to time.max_cutbacks halvings), from rest: u(0) = the Dirichlet
// values, v(0) = 0, M a(0) = f_ext - f_int(u(0)) with the schedule's values at t = 0.
//
// The energy balance after every step goes to stats.energy: kinetic + stored - work of the
// loads - work of the constraints' multipliers. The loads' work is the trapezoidal rule on
// their nodal forces over each step's displacement (exact for dead loads), a constraint's the
// trapezoidal rule on lambda dq (a cavity's p dV, a cable's tension times its pull). Newmark's
// trapezoidal rule keeps it constant up to the curvature of V(u) for a linear material;
// backward Euler dissipates it.
#pragma once

#include <vector>

#include "solvers/constraints/constraint_set.hpp"
#include "solvers/petsc_handle.hpp"
#include "solvers/stepping.hpp"
#include "solvers/stepping/state_plan.hpp"
#include "solvers/stepping/stepper.hpp"
#include "solvers/stepping/time_integrator.hpp"

namespace hs {

class DynamicStatesStepper : public Stepper {
 public:
  DynamicStatesStepper(const Config& config, Problem& problem, ConstraintSet& constraints,
                       NonlinearSolver& solver, SteppingStats& stats,
                       const ResultRecorder& recorder);

  int planned_steps() const override { return nsteps_; }
  bool done() const override { return n_ == nsteps_; }
  std::optional<StepReport> advance(Vec u) override;
  std::optional<StepReport> initial_output() const override;
  void number_output(int step) override;

  nlohmann::json position() const override;
  NamedVecs checkpoint_fields(Vec u) const override;
  NamedValues checkpoint_series() const override { return {{"energy", stats_.energy}}; }
  void resume(const Restart& restart, Vec u) override;

  int newton_iterations() const override { return stats_.newton_iterations; }
  // energy_J, kinetic_energy_J, stored_energy_J and work_J of the last step.
  void add_history(HistorySources& sources) const override;
  // `states`, `end_of_run` and the work of the loads and of each constraint (`energy.work_J`).
  void add_summary(nlohmann::json& summary) const override;

 private:
  // The fraction of the current state's ramp at time step n, a fraction of a step between
  // (1 once its time is reached, and after the last state).
  double fraction_at(double n) const;
  // Step n in `pieces` equal sub-steps from u (updated), the work of each added; "" or why a
  // solve failed.
  std::string take_substeps(Vec u, int n, int pieces);
  // The work of the solve from u_old_ to u at load factor s (the energy balance's).
  void add_work(Vec u, double s);
  // The initial acceleration and the start of the energy balance.
  void start(Vec u);
  // The loads' nodal forces on u at load factor s less the constraints' lambda g (assembled,
  // Dirichlet rows zero), after the constraints' residual at u.
  void other_loads(Vec u, double s, Vec f);
  // Kinetic and stored energy on u, and the balance with the work done so far.
  void balance(Vec u);
  void end_state(Vec u, int n);

  const Config& config_;
  Problem& problem_;
  ConstraintSet& constraints_;
  NonlinearSolver& solver_;
  SteppingStats& stats_;
  const ResultRecorder& recorder_;
  std::vector<StatePlan> plans_;
  std::vector<int64_t> ends_;  // the time step at which each state's values are reached
  int nsteps_ = 0;
  int n_ = 0;     // time steps done
  size_t k_ = 0;  // the current state
  bool started_ = false;
  double s_ = 0;  // the load factor of the last step (of t = 0 before the first)
  TimeIntegrator integrator_;
  VecHandle R_, Mv_, f_loads_, f_loads_new_, f_loads_start_, u_old_, u_start_, scratch_, g_;
  // The energy balance: the last step's kinetic and stored energy, the work of the loads and of
  // each constraint so far, and the constraints' multipliers and measures at the last step.
  double kinetic_ = 0, stored_ = 0, work_loads_ = 0;
  std::vector<double> work_, lambda_, measure_;
  nlohmann::json states_ = nlohmann::json::array();
  int unnumbered_ = -1;  // the entry of states_ whose output step comes with number_output
};

}  // namespace hs
