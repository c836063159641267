// The volumetric term k/2 (ln J)^2 (docs/formulation.md, "Nearly incompressible bodies on P1
// meshes"). With d(ln J)/dF = F^-T and d(F^-T)_ij/dF_kl = -F^-T_il F^-T_kj:
//   P = k ln J F^-T,   A_ijkl = k F^-T_ij F^-T_kl - k ln J F^-T_il F^-T_kj,
// and of J alone U' = k ln J / J, U'' = k (1 - ln J) / J^2.
#include "materials/volumetric_term.hpp"

#include <cmath>
#include <stdexcept>

#include "materials/tensor.hpp"

namespace hs {

StressResult volumetric_term(double k, const Mat3& H, bool with_tangent, bool small_strain) {
  if (small_strain) {
    const double tr = H.trace();
    StressResult s;
    s.P = k * tr * Mat3::Identity();
    s.psi = 0.5 * k * tr * tr;
    s.A.setZero();
    if (with_tangent) tensor::add_outer(s.A, k, Mat3::Identity(), Mat3::Identity());
    return s;
  }
  const double J_minus_one = tensor::det_minus_one(H);
  if (!(1.0 + J_minus_one > 0)) return inverted_result();
  const double lnJ = std::log1p(J_minus_one);
  const Mat3 FinvT = (Mat3::Identity() + H).inverse().transpose();
  StressResult s;
  s.P = k * lnJ * FinvT;
  s.psi = 0.5 * k * lnJ * lnJ;
  s.A.setZero();
  if (with_tangent) {
    tensor::add_outer(s.A, k, FinvT, FinvT);
    tensor::add_il_kj(s.A, -k * lnJ, FinvT, FinvT);
  }
  return s;
}

VolumetricValues volumetric_function(double k, double J_minus_one, bool small_strain) {
  if (small_strain) return {0.5 * k * J_minus_one * J_minus_one, k * J_minus_one, k};
  const double J = 1.0 + J_minus_one, lnJ = std::log1p(J_minus_one);
  return {0.5 * k * lnJ * lnJ, k * lnJ / J, k * (1.0 - lnJ) / (J * J)};
}

WithoutVolumetricTerm::WithoutVolumetricTerm(std::shared_ptr<const MaterialLaw> law)
    : law_(std::move(law)), k_(law_->volumetric_modulus()) {
  if (!law_->has_volumetric_term())
    throw std::logic_error("WithoutVolumetricTerm: law " + law_->name() +
                           " has no volumetric term k/2 (ln J)^2");
}

StressResult WithoutVolumetricTerm::stress(const Mat3& H, bool with_tangent) const {
  StressResult s = law_->stress(H, with_tangent);
  if (!std::isfinite(s.psi)) return s;
  const StressResult v = volumetric_term(k_, H, with_tangent, law_->small_strain());
  s.P -= v.P;
  s.psi -= v.psi;
  if (with_tangent) s.A -= v.A;
  return s;
}

}  // namespace hs
