// Compressible neo-Hookean (docs/formulation.md, "Neo-Hookean").
//   psi = mu/2 (I1 - 3) - mu ln J + lambda/2 (ln J)^2,  I1 = F:F,  J = det F,
//   P = mu (F - F^-T) + lambda ln J F^-T = F^-T (2 mu E + lambda ln J I),
// the second form (E = (F^T F - I)/2, ln J = log1p(J - 1), both from H = F - I) keeping the
// relative precision of small strains. With d(ln J)/dF = F^-T, d(F^-T)_ij/dF_kl = -F^-T_il F^-T_kj:
//   A_ijkl = mu d_ik d_jl + (mu - lambda ln J) F^-T_il F^-T_kj + lambda F^-T_ij F^-T_kl.
#include "materials/neo_hookean.hpp"

#include <cmath>

#include "materials/tensor.hpp"

namespace hs {

StressResult neo_hookean(double mu, double lambda, const Mat3& H, bool with_tangent) {
  const double J_minus_one = tensor::det_minus_one(H);
  if (!(1.0 + J_minus_one > 0)) return inverted_result();
  const double lnJ = std::log1p(J_minus_one);
  const Mat3 I = Mat3::Identity();
  const Mat3 FinvT = (I + H).inverse().transpose();
  const Mat3 E = tensor::green_lagrange(H);
  StressResult s;
  s.P = FinvT * (2.0 * mu * E + lambda * lnJ * I);
  s.psi = mu * E.trace() - mu * lnJ + 0.5 * lambda * lnJ * lnJ;  // I1 - 3 = 2 tr E
  s.A.setZero();
  if (with_tangent) {
    tensor::add_ik_lj(s.A, mu, I, I);
    tensor::add_il_kj(s.A, mu - lambda * lnJ, FinvT, FinvT);
    tensor::add_outer(s.A, lambda, FinvT, FinvT);
  }
  return s;
}

}  // namespace hs
