// Implicit dynamics at full load (Newmark, backward Euler): from rest, u(0) = the Dirichlet
// values, v(0) = 0 and M a(0) = f_ext - f_int(u(0)); one planned step per time step of
// time.dt up to time.end_time, a step whose solve fails taken again in shorter ones. After each
// step the total energy (kinetic + stored - work of the external load) goes to stats.energy:
// Newmark's trapezoidal rule conserves it for linear elasticity under dead loads, backward Euler
// dissipates it.
#pragma once

#include "solvers/petsc_handle.hpp"
#include "solvers/stepping.hpp"
#include "solvers/stepping/stepper.hpp"
#include "solvers/stepping/time_integrator.hpp"

namespace hs {

class DynamicStepper : public Stepper {
 public:
  DynamicStepper(const Config& config, Problem& problem, NonlinearSolver& solver,
                 SteppingStats& stats);

  int planned_steps() const override { return nsteps_; }
  bool done() const override { return n_ == nsteps_; }
  std::optional<StepReport> advance(Vec u) override;
  std::optional<StepReport> initial_output() const override;

  nlohmann::json position() const override;
  NamedVecs checkpoint_fields(Vec u) const override;
  NamedValues checkpoint_series() const override { return {{"energy", stats_.energy}}; }
  void resume(const Restart& restart, Vec u) override;

  int newton_iterations() const override { return stats_.newton_iterations; }

 private:
  // The initial acceleration and energy, before the first step of a run from rest.
  void start(Vec u);
  double total_energy(Vec u);
  // `pieces` equal steps of dt / pieces from u (updated); "" or why a solve failed.
  std::string take_substeps(Vec u, double dt, int pieces);

  const Config& config_;
  Problem& problem_;
  NonlinearSolver& solver_;
  SteppingStats& stats_;
  int nsteps_ = 0;
  int n_ = 0;  // time steps done
  bool started_ = false;
  TimeIntegrator integrator_;
  VecHandle R_, Mv_, f_ext_, scratch_, u_start_;
};

}  // namespace hs
