// When the bordered Newton stops iterating (docs/cavities.md, "Newton on displacements and
// pressures"): pure arithmetic on the residual's history, so that it can be tested alone.
#pragma once

#include <algorithm>
#include <functional>
#include <string>

namespace hs {

struct ResidualTest {
  double tolerance = 0;  // N: snes_atol, else 1e-9 of the force scale
  double rtol = 1e-8;    // of the first residual: snes_rtol
  // The floor no Newton step goes below: the round-off of the internal forces (costs an
  // assembly: asked for only when the residual has stopped falling) and the jump of a column
  // method's weights (one column's weight; 0 for smooth loads).
  std::function<double()> roundoff;
  double jump = 0;
};

// "" to go on, else why iteration `it` (residual r; r0 the first, r_previous the last one) has
// converged. Controls not met: never converged. `floor` receives the floor when it was asked.
inline std::string residual_verdict(const ResidualTest& test, int it, double r, double r0,
                                    double r_previous, bool controls_met, double& floor) {
  if (!controls_met) return "";
  if (r <= test.tolerance || (it > 0 && r <= test.rtol * r0)) return "converged";
  // A residual that falls by half or more is still Newton's: let it fall.
  if (it < 2 || r < 0.5 * r_previous) return "";
  if (r <= test.jump) {
    floor = test.jump;
    return "converged (|R| within one column's weight, the column method's resolution)";
  }
  floor = std::max(test.jump, test.roundoff ? test.roundoff() : 0.0);
  return r <= floor ? "converged (|R| at its round-off)" : "";
}

}  // namespace hs
