// The assembled tangent J of a Problem at u against the central difference of its residual
// along v: |(R(u + eps v) - R(u - eps v)) / (2 eps) - J v| and |J v| (error -1 if a residual
// failed). Collective.
#pragma once

#include <petscvec.h>

#include "solvers/petsc_handle.hpp"
#include "solvers/problem.hpp"

namespace hs_test {

struct TangentCheck {
  PetscReal error = -1, size = 0;
};

inline TangentCheck check_tangent(hs::Problem& problem, Mat J, Vec u, Vec v, double s,
                                  double eps = 1e-6) {
  hs::VecHandle Jv, Rp, Rm, up, um;
  for (auto* h : {&Jv, &Rp, &Rm, &up, &um}) VecDuplicate(u, h->out());
  MatMult(J, v, Jv);
  VecWAXPY(up, eps, v, u);
  VecWAXPY(um, -eps, v, u);
  TangentCheck c;
  if (!problem.residual(up, s, Rp) || !problem.residual(um, s, Rm)) return c;
  VecAXPY(Rp, -1.0, Rm);
  VecScale(Rp, 1.0 / (2 * eps));  // central difference of R along v
  VecAXPY(Rp, -1.0, Jv);
  VecNorm(Rp, NORM_2, &c.error);
  VecNorm(Jv, NORM_2, &c.size);
  return c;
}

}  // namespace hs_test
