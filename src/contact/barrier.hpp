// The contact barrier of incremental potential contact: for a gap 0 < d < dhat
//   b(d) = -(d - dhat)^2 ln(d / dhat),
// zero with its first two derivatives at d = dhat (so the energy is C2 where contact opens)
// and infinite at d = 0 (so no step that the line search accepts reaches the obstacle).
// A node of reference area A at gap d stores kappa A b(d); the contact pressure is
// -kappa b'(d), about kappa dhat^2 / d for d << dhat. Pure.
#pragma once

#include <cmath>

namespace hs {

struct BarrierValue {
  double value = 0, slope = 0, curvature = 0;  // b, db/dd, d2b/dd2
};

inline BarrierValue contact_barrier(double d, double dhat) {
  BarrierValue b;
  if (d >= dhat) return b;
  const double e = d - dhat, log_ratio = std::log(d / dhat);
  b.value = -e * e * log_ratio;
  b.slope = -2 * e * log_ratio - e * e / d;
  b.curvature = -2 * log_ratio - 4 * e / d + e * e / (d * d);
  return b;
}

}  // namespace hs
