// The control loop's side of the factorizations made in the background (docs/control.md,
// "Factorizations in the background"): at a step boundary it copies the tangent out of
// PETSc (gathered on rank 0) and hands it to a free FactorPool thread, collects the
// finished factorizations, and corrects with the newest one it has: GMRES on the current
// tangent, preconditioned by that (stale) factorization, solves each right-hand side of the
// step to the correction's tolerance. Until a background factorization is there (the first
// step) or after one failed, the step factors in line (the controller's own KSP, MUMPS by
// default), and that factorization is the preconditioner until a newer one arrives.
// Every call is collective; the threads, the factors and their solves live on rank 0.
#pragma once

#include <petscksp.h>

#include <functional>
#include <memory>
#include <string>

#include "control/factor_pool.hpp"
#include "solvers/petsc_handle.hpp"
#include "solvers/solver_options.hpp"

namespace hs {

class BackgroundFactorizations {
 public:
  // threads: factorization threads on rank 0; inline_ksp: the in-line factorization (kept
  // as the preconditioner after it is set up; this class marks it reused);
  // rtol: the correction's relative tolerance on the residual of each solve; solver: the
  // deck's options with the correction's prefix (hs_control_correction_) win over these.
  BackgroundFactorizations(MPI_Comm comm, int threads, KSP inline_ksp, double rtol,
                           const SolverConfig& solver);
  ~BackgroundFactorizations();
  BackgroundFactorizations(const BackgroundFactorizations&) = delete;
  BackgroundFactorizations& operator=(const BackgroundFactorizations&) = delete;

  struct Poll {
    bool adopted = false;  // a newer background factorization is now the preconditioner
    bool failed = false;   // a background factorization failed (error says why)
    std::string error;
    double factor_ms = 0;  // the adopted one's time in its thread
  };
  // At a step boundary: the finished factorizations; adopts the newest if it is newer than
  // the preconditioner.
  Poll poll();
  // The in-line factorization just set up on the tangent of step `state` becomes the
  // preconditioner.
  void use_inline(int state);
  bool has_preconditioner() const { return source_ != Source::none; }
  int preconditioner_state() const { return state_; }
  // Hands a copy of J (the tangent of step `state`) to a free thread; false if none is free.
  bool submit_if_idle(Mat J, int state);
  // GMRES on J with the preconditioner (J must stay as it is while the KSP is used).
  KSP correction(Mat J);
  int threads() const { return threads_; }
  // Blocks until the threads are idle (tests: makes the adoption of a factorization
  // deterministic).
  void wait_idle();
  // Applied on rank 0 to every copy of the tangent before a thread factors it (tests: a copy
  // made indefinite, so that the background factorization really fails).
  void set_copy_filter(std::function<void(CsrMatrix&)> filter) { filter_ = std::move(filter); }

 private:
  enum class Source { none, inline_ksp, background };
  static PetscErrorCode apply(PC pc, Vec x, Vec y);

  MPI_Comm comm_;
  int rank_ = 0, threads_ = 0;
  KSP inline_ksp_;
  SolverOptions options_;  // before the KSP: it outlives it
  KspHandle correction_;
  std::unique_ptr<FactorPool> pool_;        // rank 0
  std::unique_ptr<CholeskyFactor> factor_;  // rank 0: the adopted background factorization
  Source source_ = Source::none;
  int state_ = -1;
  VecScatterHandle to_zero_;  // the whole vector on rank 0, for the factor's solves
  VecHandle x0_, y0_;
  std::function<void(CsrMatrix&)> filter_;
};

}  // namespace hs
