// Saint Venant-Kirchhoff (docs/formulation.md, "Saint Venant-Kirchhoff").
//   E = (F^T F - I)/2,  psi = mu E:E + lambda/2 tr(E)^2,  S = lambda tr(E) I + 2 mu E,  P = F S.
// With dE_mj/dF_kl = (d_lm F_kj + F_km d_lj)/2 the tangent is
//   A_ijkl = d_ik S_lj + lambda F_ij F_kl + mu (F_il F_kj + (F F^T)_ik d_lj).
// The energy is defined for any F; det F <= 0 is still reported as an inverted point.
#include "materials/saint_venant_kirchhoff.hpp"

#include "materials/tensor.hpp"

namespace hs {

StressResult saint_venant_kirchhoff(double mu, double lambda, const Mat3& H, bool with_tangent) {
  if (!(1.0 + tensor::det_minus_one(H) > 0)) return inverted_result();
  const Mat3 I = Mat3::Identity();
  const Mat3 F = I + H;
  const Mat3 E = tensor::green_lagrange(H);
  const double trE = E.trace();
  const Mat3 S = lambda * trE * I + 2.0 * mu * E;
  StressResult s;
  s.P = F * S;
  s.psi = mu * E.squaredNorm() + 0.5 * lambda * trE * trE;
  s.A.setZero();
  if (with_tangent) {
    tensor::add_ik_lj(s.A, 1.0, I, S);
    tensor::add_outer(s.A, lambda, F, F);
    tensor::add_il_kj(s.A, mu, F, F);
    tensor::add_ik_lj(s.A, mu, F * F.transpose(), I);
  }
  return s;
}

}  // namespace hs
