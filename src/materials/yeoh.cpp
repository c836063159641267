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

std::vector<std::string> YeohLaw::keys() { return {"C1", "C2", "C3", "nu"}; }

std::shared_ptr<const MaterialLaw> YeohLaw::parse(const DeckReader& r, const YAML::Node& node,
                                                  const std::string& key) {
  const YAML::Node c1 = required(r, node, key, "C1");
  const double C1 = r.number(c1, child_key(key, "C1"));
  require(C1 > 0, r, c1, child_key(key, "C1"),
          "must be > 0 (the small-strain shear modulus is 2 C1), got " + format_number(C1));
  const double C2 = node["C2"] ? r.number(node["C2"], child_key(key, "C2")) : 0.0;
  const double C3 = node["C3"] ? r.number(node["C3"], child_key(key, "C3")) : 0.0;
  const double nu = parse_poisson_ratio(r, node, key);
  const ElasticConstants c = elastic_constants_from_mu_nu(2 * C1, nu);
  require(std::isfinite(c.E) && std::isfinite(c.lambda), r, c1, child_key(key, "C1"),
          "gives E = " + format_number(c.E) + ", lambda = " + format_number(c.lambda) +
              " with nu = " + format_number(nu) + ", beyond a double");
  return std::make_shared<YeohLaw>(c, C2, C3);
}

StressResult YeohLaw::stress(const Mat3& H, bool with_tangent) const {
  return yeoh(C1(), C2_, C3_, constants_.lambda + 2.0 * constants_.mu / 3.0, H, with_tangent);
}

void YeohLaw::print(YAML::Emitter& out) const {
  print_number(out, "C1", C1());
  print_number(out, "C2", C2_);
  print_number(out, "C3", C3_);
  print_number(out, "nu", constants_.nu);
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
