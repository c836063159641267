// What the states of a deck report at the end of each (solvers/stepping/states_stepper.hpp)
// beside their cavities and cables: the orientation and the displacement of the deck's tip.
#pragma once

#include <petscvec.h>

#include <array>
#include <string>

#include "solvers/problem.hpp"

namespace hs {

// The orientation of a face group's mean normal (summary.json's per-state `tip`), in degrees:
// inclination_deg, below the plane normal to gravity (positive: tilted towards gravity),
// asin(n . g / |g|): the paper's tip angle when the face is vertical in the undeformed mesh;
// rotation_deg, the angle between the mean normal now and in the undeformed mesh, which
// means the same for a face of any orientation.
// displacement: the mean displacement of the face (its centroid's, Problem::mean_displacement),
// which says how far the tip moved whatever the gravity (the inclination is 0 without one).
struct TipOrientation {
  double inclination_deg = 0;
  double rotation_deg = 0;
  std::array<double, 3> displacement{0, 0, 0};
};
TipOrientation tip_orientation(Problem& problem, const std::string& group,
                               const std::array<double, 3>& gravity, Vec u);

}  // namespace hs
