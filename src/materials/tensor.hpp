// Building blocks of fourth-order tangents stored as 9x9 matrices, A(3i+j, 3k+l) = dP_ij/dF_kl.
// Each adds one index pattern; every tangent of materials/ is a sum of these three
// (and of the isochoric first-invariant block below, made of them).
#pragma once

#include <cmath>

#include "materials/material.hpp"

namespace hs::tensor {

// Kinematics from the displacement gradient H = F - I, free of the cancellation in F - I,
// F^T F - I or det F - 1 that would leave an absolute error of 1e-16 (times the stiffness) on
// strains that may be as small as 1e-9.

// Green-Lagrange strain E = (F^T F - I)/2 = (H + H^T + H^T H)/2.
inline Mat3 green_lagrange(const Mat3& H) { return 0.5 * (H + H.transpose() + H.transpose() * H); }

// det(I + H) - 1 = tr H + ((tr H)^2 - tr(H^2))/2 + det H.
inline double det_minus_one(const Mat3& H) {
  const double t = H.trace();
  return t + 0.5 * (t * t - (H * H).trace()) + H.determinant();
}

// The isochoric first invariant's part J^-2/3 and its excess I1b - 3 = J^-2/3 tr C - 3, from
// ln J and tr E: I1b - 3 = 3 (g - 1) + 2 g tr E with g - 1 = expm1(-2/3 ln J) (Gent, Yeoh).
struct IsochoricI1 {
  double g;       // J^-2/3
  double excess;  // I1b - 3
};
inline IsochoricI1 isochoric_I1(double lnJ, double trE) {
  const double g_minus_one = std::expm1(-2.0 / 3.0 * lnJ);
  const double g = 1.0 + g_minus_one;
  return {g, 3.0 * g_minus_one + 2.0 * g * trE};
}

// Deviatoric part X - tr(X)/3 I.
inline Mat3 deviator(const Mat3& X) { return X - X.trace() / 3.0 * Mat3::Identity(); }

// Row-major flattening of a 3x3 matrix: v(3i + j) = X(i, j).
inline Eigen::Matrix<double, 9, 1> flatten(const Mat3& X) {
  Eigen::Matrix<double, 9, 1> v;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) v(3 * i + j) = X(i, j);
  return v;
}

// A_ijkl += c X_ij Y_kl (e.g. lambda I (x) I, or F^-T (x) F^-T from d(ln J)/dF).
inline void add_outer(Tangent& A, double c, const Mat3& X, const Mat3& Y) {
  A.noalias() += c * flatten(X) * flatten(Y).transpose();
}

// A_ijkl += c X_ik Y_lj (with X = Y = I: the identity dF/dF).
inline void add_ik_lj(Tangent& A, double c, const Mat3& X, const Mat3& Y) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l) A(3 * i + j, 3 * k + l) += c * X(i, k) * Y(l, j);
}

// A_ijkl += c X_il Y_kj (with X = Y = F^-T: minus d(F^-T)/dF; with X = Y = I: d(F^T)/dF).
inline void add_il_kj(Tangent& A, double c, const Mat3& X, const Mat3& Y) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l) A(3 * i + j, 3 * k + l) += c * X(i, l) * Y(k, j);
}

// A += a [2 Id - 4/3 (F (x) F^-T + F^-T (x) F) + 4/9 I1 F^-T (x) F^-T + 2/3 I1 D], D_ijkl =
// F^-T_il F^-T_kj: the second derivative of I1b = J^-2/3 I1 times a / J^-2/3, the first
// invariant's part of the isochoric laws (Mooney-Rivlin: a = c1 J^-2/3; Gent: a = w J^-2/3).
inline void add_isochoric_I1_tangent(Tangent& A, double a, const Mat3& F, const Mat3& FinvT,
                                     double I1) {
  const Mat3 I = Mat3::Identity();
  add_ik_lj(A, 2.0 * a, I, I);
  add_outer(A, -4.0 / 3.0 * a, F, FinvT);
  add_outer(A, -4.0 / 3.0 * a, FinvT, F);
  add_outer(A, 4.0 / 9.0 * a * I1, FinvT, FinvT);
  add_il_kj(A, 2.0 / 3.0 * a * I1, FinvT, FinvT);
}

}  // namespace hs::tensor
