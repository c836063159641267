// Compressible Yeoh on the isochoric first invariant (docs/formulation.md, "Yeoh").
//   C = F^T F,  I1 = tr C,  I1b = J^-2/3 I1,  x = I1b - 3,
//   psi = C1 x + C2 x^2 + C3 x^3 + kappa/2 (ln J)^2.
// As in gent.cpp, with w = dpsi/dI1b = C1 + 2 C2 x + 3 C3 x^2 the deviatoric part is
// Mooney-Rivlin's first-invariant term with c1 -> w: with g = J^-2/3,
//   dI1b/dF = g (2 F - 2/3 I1 F^-T) = 4 g F^-T dev E,
//   P = F^-T [4 w g dev E + kappa ln J I],
// and the tangent adds w' dI1b/dF (x) dI1b/dF, w' = dw/dI1b = 2 C2 + 6 C3 x:
//   A = w g [2 Id - 4/3 (F (x) F^-T + F^-T (x) F) + 4/9 I1 F^-T (x) F^-T + 2/3 I1 D]
//     + w' dI1b/dF (x) dI1b/dF + kappa [F^-T (x) F^-T - ln J D],   D_ijkl = F^-T_il F^-T_kj.
// Small strains keep their precision: E and ln J come from H = F - I, and
// x = 3 (g - 1) + 2 g tr E with g - 1 = expm1(-2/3 ln J). At F = I, x = 0, w = C1 and the
// w' term vanishes: the small-strain limit is linear elasticity with mu = 2 C1 and kappa.
#include "materials/yeoh.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "materials/tensor.hpp"

namespace hs {

StressResult yeoh(double C1, double C2, double C3, double kappa, const Mat3& H, bool with_tangent) {
  const double J_minus_one = tensor::det_minus_one(H);
  if (!(1.0 + J_minus_one > 0)) return inverted_result();
  const double lnJ = std::log1p(J_minus_one);
  const Mat3 E = tensor::green_lagrange(H);
  const double trE = E.trace();
  const auto [g, x] = tensor::isochoric_I1(lnJ, trE);
  const double w = C1 + x * (2.0 * C2 + 3.0 * C3 * x);
  const Mat3 I = Mat3::Identity();
  const Mat3 F = I + H;
  const Mat3 FinvT = F.inverse().transpose();
  const Mat3 dev_E = tensor::deviator(E);

  StressResult s;
  s.P = FinvT * (4.0 * w * g * dev_E + kappa * lnJ * I);
  s.psi = x * (C1 + x * (C2 + x * C3)) + 0.5 * kappa * lnJ * lnJ;
  s.A.setZero();
  if (!with_tangent) return s;

  const double I1 = 3.0 + 2.0 * trE;
  tensor::add_isochoric_I1_tangent(s.A, w * g, F, FinvT, I1);
  const Mat3 dI1b = 4.0 * g * FinvT * dev_E;
  tensor::add_outer(s.A, 2.0 * C2 + 6.0 * C3 * x, dI1b, dI1b);
  tensor::add_outer(s.A, kappa, FinvT, FinvT);
  tensor::add_il_kj(s.A, -kappa * lnJ, FinvT, FinvT);
  return s;
}

double yeoh_softening_onset(double C1, double C2, double C3) {
  // Roots of 3 C3 x^2 + 2 C2 x + C1, in the form that does not cancel (q and C1 / q).
  const double a = 3.0 * C3, b = 2.0 * C2, c = C1;
  const double none = std::numeric_limits<double>::infinity();
  if (a == 0) return b < 0 ? -c / b : none;
  const double discriminant = b * b - 4.0 * a * c;
  if (discriminant < 0) return none;
  const double q = -0.5 * (b + std::copysign(std::sqrt(discriminant), b));
  double onset = none;
  for (double root : {q / a, c / q})
    if (root > 0) onset = std::min(onset, root);
  return onset;
}

const LawKeyTable<YeohParameters>& YeohLaw::keys() {
  using P = YeohParameters;
  static const LawKeyTable<P> keys = {
      LawKeys::number_key<P>(
          "C1", &P::C1, above(0, "the small-strain shear modulus is 2 C1"),
          "the first coefficient (Pa): ψ = C1 x + C2 x² + C3 x³ + κ/2 (ln J)², x = Ī₁ − 3; the "
          "small-strain shear modulus is μ = 2 C1")
          .needed(),
      LawKeys::number_key<P>(
          "C2", &P::C2, any_number(),
          "the second coefficient (Pa), of either sign as published fits have them"),
      LawKeys::number_key<P>("C3", &P::C3, any_number(), "the third coefficient (Pa), as `C2`"),
      LawKeys::number_key<P>("nu", &P::nu, poisson_ratio_limit(),
                             "Poisson's ratio: the bulk modulus κ = 2μ (1 + ν) / (3 (1 − 2ν)); "
                             "0.5 is exact incompressibility (P1 meshes, docs/formulation.md)")
          .needed(),
  };
  return keys;
}

std::shared_ptr<const MaterialLaw> YeohLaw::make(const DeckReader& r, const YAML::Node& node,
                                                 const std::string& key, const Parameters& read) {
  const ElasticConstants c = elastic_constants_from_mu_nu(2 * read.C1, read.nu);
  require(std::isfinite(c.E) && std::isfinite(c.lambda), r, node["C1"], child_key(key, "C1"),
          "gives E = " + format_number(c.E) + ", lambda = " + format_number(c.lambda) +
              " with nu = " + format_number(read.nu) + ", beyond a double");
  return std::make_shared<YeohLaw>(c, read.C2, read.C3);
}

StressResult YeohLaw::stress(const Mat3& H, bool with_tangent) const {
  return yeoh(C1(), C2_, C3_, volumetric_modulus(), H, with_tangent);
}

std::string YeohLaw::derived_values() const {
  std::string text = "mu = " + format_number(constants_.mu) +
                     ", lambda = " + format_number(constants_.lambda) +
                     ", E = " + format_number(constants_.E);
  const double onset = yeoh_softening_onset(C1(), C2_, C3_);
  if (std::isfinite(onset))
    text += "; dpsi/dI1b < 0 past I1b - 3 = " + format_number(onset) + " (the fit softens there)";
  return text;
}

}  // namespace hs
