// Compressible Gent on the isochoric first invariant (docs/formulation.md, "Gent").
//   C = F^T F,  I1 = tr C,  I1b = J^-2/3 I1,  x = (I1b - 3)/Jm < 1,
//   psi = -mu Jm/2 ln(1 - x) + kappa/2 (ln J)^2.
// With w = dpsi/dI1b = mu / (2 (1 - x)) the deviatoric part is that of Mooney-Rivlin's first
// invariant with c1 -> w (mooney_rivlin.cpp): with g = J^-2/3,
//   dI1b/dF = g (2 F - 2/3 I1 F^-T) = 4 g F^-T dev E,
//   P = F^-T [4 w g dev E + kappa ln J I],
// and the tangent adds the stiffening w' dI1b/dF (x) dI1b/dF, w' = w / (Jm (1 - x)):
//   A = w g [2 Id - 4/3 (F (x) F^-T + F^-T (x) F) + 4/9 I1 F^-T (x) F^-T + 2/3 I1 D]
//     + w' dI1b/dF (x) dI1b/dF + kappa [F^-T (x) F^-T - ln J D],   D_ijkl = F^-T_il F^-T_kj.
// Small strains keep their precision: E and ln J come from H = F - I, and
// I1b - 3 = 3 (g - 1) + 2 g tr E with g - 1 = expm1(-2/3 ln J). At x -> 0 (small strain, or
// Jm -> inf) w -> mu/2: the small-strain limit is linear elasticity with mu, lambda.
#include "materials/gent.hpp"

#include <cmath>

#include "materials/tensor.hpp"

namespace hs {

StressResult gent(double mu, double Jm, double kappa, const Mat3& H, bool with_tangent) {
  const double J_minus_one = tensor::det_minus_one(H);
  if (!(1.0 + J_minus_one > 0)) return inverted_result();
  const double lnJ = std::log1p(J_minus_one);
  const Mat3 E = tensor::green_lagrange(H);
  const double trE = E.trace();
  const auto [g, excess] = tensor::isochoric_I1(lnJ, trE);
  const double x = excess / Jm;
  // Past the limiting chain the energy is not defined: an inverted point for the caller.
  if (!(x < 1.0)) return inverted_result();
  const double w = 0.5 * mu / (1.0 - x);
  const Mat3 I = Mat3::Identity();
  const Mat3 F = I + H;
  const Mat3 FinvT = F.inverse().transpose();
  const Mat3 dev_E = tensor::deviator(E);

  StressResult s;
  s.P = FinvT * (4.0 * w * g * dev_E + kappa * lnJ * I);
  s.psi = -0.5 * mu * Jm * std::log1p(-x) + 0.5 * kappa * lnJ * lnJ;
  s.A.setZero();
  if (!with_tangent) return s;

  const double I1 = 3.0 + 2.0 * trE;
  tensor::add_isochoric_I1_tangent(s.A, w * g, F, FinvT, I1);
  const Mat3 dI1b = 4.0 * g * FinvT * dev_E;
  tensor::add_outer(s.A, w / (Jm * (1.0 - x)), dI1b, dI1b);
  tensor::add_outer(s.A, kappa, FinvT, FinvT);
  tensor::add_il_kj(s.A, -kappa * lnJ, FinvT, FinvT);
  return s;
}

const LawKeyTable<GentParameters>& GentLaw::keys() {
  static const LawKeyTable<GentParameters> keys = [] {
    LawKeyTable<GentParameters> keys = elastic_constant_keys<GentParameters>();
    keys.push_back(LawKeys::number_key<GentParameters>(
                       "Jm", &GentParameters::Jm, above(0, "the limit of I1b - 3"),
                       "the limit of Ī₁ − 3 (the chains' extensibility): ψ = −μ Jm/2 ln(1 − (Ī₁ − "
                       "3)/Jm) + κ/2 (ln J)², κ = λ + 2μ/3; a smaller Jm stiffens sooner")
                       .needed());
    return keys;
  }();
  return keys;
}

std::shared_ptr<const MaterialLaw> GentLaw::make(const DeckReader& r, const YAML::Node& node,
                                                 const std::string& key, const Parameters& read) {
  return std::make_shared<GentLaw>(resolve_elastic_constants(r, node, key, read), read.Jm);
}

StressResult GentLaw::stress(const Mat3& H, bool with_tangent) const {
  return gent(constants_.mu, Jm_, volumetric_modulus(), H, with_tangent);
}

}  // namespace hs
