// Newton's method for the displacements and the cavity pressures together (the bordered
// system of solvers/constraints/constraint_set.hpp). Each iteration solves
//   [ J    -G ] [du     ]     [R]          J du = -R + G dlambda + Q eta
//   [ A     B ] [dlambda] = - [c],  with   eta_h = g_h^T du (hydraulic cavities, Q = W / V)
// by block elimination (solvers/bordered_system.hpp): one factorization of the sparse tangent J
// (PETSc KSP, with the options of prefix hs_bordered_: MUMPS by default) and 1 + m + m_h
// solves with it, then a dense system of size m + m_h for dlambda and eta. Full steps, shortened
// only where a trial inverts an element. docs/cavities.md says why this is not a SNES: SNES would
// need a shell matrix and a shell preconditioner doing this same elimination, on a composite
// vector.
#pragma once

#include <petscksp.h>

#include <string>
#include <vector>

#include "solvers/bordered_system.hpp"
#include "solvers/constraints/constraint_set.hpp"
#include "solvers/newton_solver.hpp"
#include "solvers/solver_options.hpp"

namespace hs {

class BorderedNewton : public NonlinearSolver {
 public:
  // The preset is chosen for the tangent's kind (run_setup.cpp works it out for a deck).
  BorderedNewton(Problem& problem, ConstraintSet& constraints, const SolverConfig& solver,
                 TangentKind tangent);
  BorderedNewton(const BorderedNewton&) = delete;
  BorderedNewton& operator=(const BorderedNewton&) = delete;

  // Solves at load factor s from u and the cavities' current pressures; on success u and the
  // pressures hold the solution.
  NewtonResult solve(Vec u, double s) override;
  // The norm of the full external load (gravity, pressure loads): with the pressure forces,
  // it sets the residual tolerance 1e-9 F.
  void set_load_norm(double norm) { load_norm_ = norm; }
  double solve_seconds() const override { return solve_s_; }
  bool newton_step(Vec u, double s, Vec du, std::vector<double>& dmultipliers) override;
  double constraint_seconds() const { return constraint_s_; }
  // The tangent's kind it was made for: the inverse controller's KSP takes the same preset.
  TangentKind tangent() const { return tangent_; }
  KSP ksp() const { return ksp_; }

 private:
  // The Newton iterations at the volume multipliers as they are (solvers/incompressibility.hpp
  // repeats them for exactly incompressible bodies).
  NewtonResult solve_once(Vec u, double s);
  // Moves u and the multipliers (lambda) along the step du_, zeta, halved where a trial leaves
  // the domain (and, with self-contact, where it lowers neither |R| nor, at held pressures,
  // the energy); c and r_norm become the new point's. False, with the reason, when no step is
  // left (the cavities are then put back at u).
  bool take_step(Vec u, double s, const Eigen::VectorXd& zeta, std::vector<double>& lambda,
                 std::vector<double>& c, double& r_norm, std::string& reason);

  Problem& problem_;
  ConstraintSet& constraints_;
  TangentKind tangent_;
  SolverOptions options_;  // before the KSP: it outlives it
  KspHandle ksp_;
  int pattern_version_ = 0;  // the tangent pattern the preconditioner was set up for
  void reset_if_pattern_grew();
  MatHandle J_;
  VecHandle R_, du_, u_trial_;
  BorderedSystem system_;
  ConstraintLinearization lin_;
  double load_norm_ = 0, solve_s_ = 0, constraint_s_ = 0;
  int max_it_ = 30;
  double atol_ = -1, rtol_ = 1e-8;  // atol < 0: 1e-9 of the force scale
  bool monitor_ = false;            // -hs_bordered_monitor: one line per iteration
  bool volume_monitor_ = false;     // -hs_volume_monitor: a line per raise of the multipliers
};

}  // namespace hs
