#include "materials/material.hpp"

#include <cmath>
#include <limits>

namespace hs {

Mat3 MaterialLaw::cauchy_stress(const Mat3& F) const {
  return stress(F - Mat3::Identity(), false).P * F.transpose() / F.determinant();
}

StressResult inverted_result() {
  StressResult s;
  s.P.setConstant(std::numeric_limits<double>::quiet_NaN());
  s.A.setConstant(std::numeric_limits<double>::quiet_NaN());
  s.psi = std::numeric_limits<double>::infinity();
  return s;
}

double von_mises(const Mat3& sigma) {
  const Mat3 s = sigma - sigma.trace() / 3.0 * Mat3::Identity();
  return std::sqrt(1.5 * s.squaredNorm());
}

}  // namespace hs
