// Building blocks of fourth-order tangents stored as 9x9 matrices, A(3i+j, 3k+l) = dP_ij/dF_kl.
// Each adds one index pattern; every tangent of materials/ is a sum of these three.
#pragma once

#include "materials/material.hpp"

namespace hs::tensor {

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

}  // namespace hs::tensor
