// Compressible Mooney-Rivlin on the isochoric invariants (docs/formulation.md, "Mooney-Rivlin").
//   C = F^T F,  I1 = tr C,  I2 = (I1^2 - C:C)/2,  I1b = J^-2/3 I1,  I2b = J^-4/3 I2,
//   psi = c1 (I1b - 3) + c2 (I2b - 3) + kappa/2 (ln J)^2.
// Small-strain limit: shear modulus 2 (c1 + c2), bulk modulus kappa. The (ln J)^2 volumetric
// term (rather than (J - 1)^2) makes psi infinite as J -> 0, a barrier against inversion.
// With g = J^-2/3, h = J^-4/3 and dJ/dF = J F^-T:
//   dI1b/dF = g (2 F - 2/3 I1 F^-T)
//   dI2b/dF = h Q,  Q = 2 (I1 F - F C) - 4/3 I2 F^-T
//   P = c1 dI1b/dF + c2 dI2b/dF + kappa ln J F^-T.
// Written on E = (C - I)/2 (from H = F - I, keeping the precision of small strains), with
// t = tr E: dev C = 2 dev E and dev(I1 C - C^2) = 2 dev((1 + 2t) E - 2 E^2), so
//   P = F^-T [4 c1 g dev E + 4 c2 h dev((1 + 2t) E - 2 E^2) + kappa ln J I].
// Differentiating once more (D_ijkl = F^-T_il F^-T_kj, (X (x) Y)_ijkl = X_ij Y_kl):
//   A1 = c1 g [2 Id - 4/3 (F (x) F^-T + F^-T (x) F) + 4/9 I1 F^-T (x) F^-T + 2/3 I1 D]
//   dQ = 4 F (x) F + 2 I1 Id - 2 d(F C) - 8/3 F^-T (x) (I1 F - F C) + 4/3 I2 D,
//        d(F C)_ijkl = d_ik C_lj + F_il F_kj + (F F^T)_ik d_lj
//   A2 = c2 h [dQ - 4/3 Q (x) F^-T]
//   A3 = kappa [F^-T (x) F^-T - ln J D].
#include "materials/mooney_rivlin.hpp"

#include <cmath>

#include "materials/tensor.hpp"

namespace hs {

StressResult mooney_rivlin(double c1, double c2, double kappa, const Mat3& H, bool with_tangent) {
  const double J_minus_one = tensor::det_minus_one(H);
  if (!(1.0 + J_minus_one > 0)) return inverted_result();
  const Mat3 I = Mat3::Identity();
  const Mat3 F = I + H;
  const double lnJ = std::log1p(J_minus_one);
  const double g = std::exp(-2.0 / 3.0 * lnJ);
  const double h = g * g;
  const Mat3 FinvT = F.inverse().transpose();
  const Mat3 E = tensor::green_lagrange(H);
  const Mat3 C = I + 2.0 * E;
  const Mat3 FC = F * C;
  const double I1 = C.trace();
  const double I2 = 0.5 * (I1 * I1 - C.squaredNorm());
  const Mat3 dev_E = tensor::deviator(E);
  const Mat3 dev_E2 = tensor::deviator((1.0 + 2.0 * E.trace()) * E - 2.0 * E * E);
  const Mat3 Q = 4.0 * FinvT * dev_E2;  // = 2 (I1 F - F C) - 4/3 I2 F^-T

  StressResult s;
  s.P = FinvT * (4.0 * c1 * g * dev_E + 4.0 * c2 * h * dev_E2 + kappa * lnJ * I);
  s.psi = c1 * (g * I1 - 3.0) + c2 * (h * I2 - 3.0) + 0.5 * kappa * lnJ * lnJ;
  s.A.setZero();
  if (!with_tangent) return s;

  // First invariant part.
  tensor::add_isochoric_I1_tangent(s.A, c1 * g, F, FinvT, I1);
  // Second invariant part.
  const double a2 = c2 * h;
  tensor::add_outer(s.A, 4.0 * a2, F, F);
  tensor::add_ik_lj(s.A, 2.0 * a2 * I1, I, I);
  tensor::add_ik_lj(s.A, -2.0 * a2, I, C);
  tensor::add_il_kj(s.A, -2.0 * a2, F, F);
  tensor::add_ik_lj(s.A, -2.0 * a2, F * F.transpose(), I);
  tensor::add_outer(s.A, -8.0 / 3.0 * a2, FinvT, I1 * F - FC);
  tensor::add_il_kj(s.A, 4.0 / 3.0 * a2 * I2, FinvT, FinvT);
  tensor::add_outer(s.A, -4.0 / 3.0 * a2, Q, FinvT);
  // Volumetric part.
  tensor::add_outer(s.A, kappa, FinvT, FinvT);
  tensor::add_il_kj(s.A, -kappa * lnJ, FinvT, FinvT);
  return s;
}

const LawKeyTable<MooneyRivlinParameters>& MooneyRivlinLaw::keys() {
  using P = MooneyRivlinParameters;
  static const LawKeyTable<P> keys = [] {
    LawKeyTable<P> keys = elastic_constant_keys<P>();
    keys.push_back(
        LawKeys::optional_number_key<P>("c1", &P::c1,
                                        "the first invariant's coefficient: ψ = c1 (Ī₁ − 3) + c2 "
                                        "(Ī₂ − 3) + κ/2 (ln J)², κ = λ + "
                                        "2μ/3; c1 + c2 > 0 (the small-strain shear modulus "
                                        "is 2 (c1 + c2))")
            .defaults_to("μ/2"));
    keys.push_back(LawKeys::number_key<P>("c2", &P::c2, any_number(),
                                          "the second invariant's coefficient, see `c1`"));
    return keys;
  }();
  return keys;
}

std::shared_ptr<const MaterialLaw> MooneyRivlinLaw::make(const DeckReader& r,
                                                         const YAML::Node& node,
                                                         const std::string& key,
                                                         const Parameters& read) {
  const ElasticConstants constants = resolve_elastic_constants(r, node, key, read);
  const double c1 = read.c1.value_or(constants.mu / 2), c2 = read.c2;
  require(c1 + c2 > 0, r, node, child_key(key, "c1"),
          "c1 + c2 must be > 0 (the small-strain shear modulus is 2 (c1 + c2))");
  return std::make_shared<MooneyRivlinLaw>(constants, c1, c2);
}

StressResult MooneyRivlinLaw::stress(const Mat3& H, bool with_tangent) const {
  // Bulk modulus of the small-strain limit; the shear modulus there is 2 (c1 + c2).
  return mooney_rivlin(c1_, c2_, volumetric_modulus(), H, with_tangent);
}

}  // namespace hs
