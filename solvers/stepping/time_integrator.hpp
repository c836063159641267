// The implicit time integration both dynamic steppers share (Newmark, backward Euler): the
// consistent mass matrix, the velocity and acceleration, the predictor of a step and the update
// after it. A step solves c M (u - u_pred) + f_int(u) - f_ext = 0 with
//   u_pred = u + dt v + dt^2 (1/2 - beta) a,  c = 1 / (beta dt^2)   (Newmark),
//   u_pred = u + dt v,                        c = 1 / dt^2           (backward Euler),
// and then a_new = c (u - u_pred), v += dt ((1 - gamma) a + gamma a_new) or dt a_new.
#pragma once

#include "solvers/petsc_handle.hpp"
#include "solvers/problem.hpp"

namespace hs {

class TimeIntegrator {
 public:
  // The mass matrix reads the mass solve's options (hs_mass_: a matrix's -mat_view, as the
  // tangent reads its solver's). v = a = 0.
  TimeIntegrator(const Config& config, Problem& problem);

  // a(0) = -M^-1 R (R the residual f_int - f_ext of the start): CG on the mass matrix, its
  // solver set here (no preset, only the options with its prefix).
  void start(Vec R);
  // u_pred and c from the configuration u at the start of a step of length dt.
  void predict(Vec u, double dt);
  // a and v from the solution u of that step.
  void update(Vec u, double dt);
  // v and a kept, and put back: a time step whose solve failed is taken again from its start
  // in shorter steps (its cutbacks).
  void save();
  void restore();

  // While it lives, the problem carries the inertia term (the step's solve), and it lets go of
  // it on every way out (a failed step leaves by an exception).
  class Scope {
   public:
    explicit Scope(TimeIntegrator& t) : problem_(t.problem_) { problem_.set_inertia(&t.inertia_); }
    ~Scope() { problem_.set_inertia(nullptr); }
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    Problem& problem_;
  };

  Mat mass() const { return inertia_.M; }
  Vec velocity() const { return v_; }
  Vec acceleration() const { return a_; }

 private:
  const Config& config_;
  Problem& problem_;
  InertiaTerm inertia_;
  VecHandle v_, a_, a_new_, v_saved_, a_saved_;
};

}  // namespace hs
