// Small-strain linear elasticity (docs/formulation.md, "Linear elastic").
//   eps = (H + H^T)/2  (H = F - I),  psi = mu eps:eps + lambda/2 tr(eps)^2,
//   P = sigma = lambda tr(eps) I + 2 mu eps,
//   A_ijkl = lambda d_ij d_kl + mu (d_ik d_jl + d_il d_jk)   (constant).
// Not objective: it is meant for small displacements and as the small-strain reference.
#include "materials/linear_elastic.hpp"

#include "materials/tensor.hpp"

namespace hs {

StressResult linear_elastic(double mu, double lambda, const Mat3& H, bool with_tangent) {
  const Mat3 I = Mat3::Identity();
  const Mat3 eps = 0.5 * (H + H.transpose());
  const double tr = eps.trace();
  StressResult s;
  s.P = lambda * tr * I + 2.0 * mu * eps;
  s.psi = mu * eps.squaredNorm() + 0.5 * lambda * tr * tr;
  s.A.setZero();
  if (with_tangent) {
    tensor::add_outer(s.A, lambda, I, I);
    tensor::add_ik_lj(s.A, mu, I, I);
    tensor::add_il_kj(s.A, mu, I, I);
  }
  return s;
}

Mat3 LinearElasticLaw::cauchy_stress(const Mat3& F) const {
  return stress(F - Mat3::Identity(), false).P;
}

}  // namespace hs
