// Compressible neo-Hookean (docs/formulation.md, "Neo-Hookean").
//   psi = mu/2 (I1 - 3) - mu ln J + lambda/2 (ln J)^2,  I1 = F:F,  J = det F,
//   P = mu (F - F^-T) + lambda ln J F^-T,
// and with d(ln J)/dF = F^-T, d(F^-T)_ij/dF_kl = -F^-T_il F^-T_kj:
//   A_ijkl = mu d_ik d_jl + (mu - lambda ln J) F^-T_il F^-T_kj + lambda F^-T_ij F^-T_kl.
#include <cmath>

#include "materials/models.hpp"
#include "materials/tensor.hpp"

namespace hs {

StressResult neo_hookean(double mu, double lambda, const Mat3& F, bool with_tangent) {
  const double J = F.determinant();
  if (!(J > 0)) return inverted_result();
  const double lnJ = std::log(J);
  const Mat3 FinvT = F.inverse().transpose();
  StressResult s;
  s.P = mu * (F - FinvT) + lambda * lnJ * FinvT;
  s.psi = 0.5 * mu * (F.squaredNorm() - 3.0) - mu * lnJ + 0.5 * lambda * lnJ * lnJ;
  s.A.setZero();
  if (with_tangent) {
    const Mat3 I = Mat3::Identity();
    tensor::add_ik_lj(s.A, mu, I, I);
    tensor::add_il_kj(s.A, mu - lambda * lnJ, FinvT, FinvT);
    tensor::add_outer(s.A, lambda, FinvT, FinvT);
  }
  return s;
}

}  // namespace hs
