// Where `hydrosoft reduce` solves the full model (docs/reduced_models.md, "Training"): the
// training design, points of the unit box [0, 1]^m of m actuators (the caller scales each
// coordinate to its actuator's [min, max]), in the order they are solved, and which of them are
// held back to measure the model.
#pragma once

#include <vector>

namespace hs {

struct TrainingDesign {
  std::vector<std::vector<double>> points;  // in [0, 1]^m, in solving order
  std::vector<bool> held_back;
};

// The full grid of n points a dimension (n^m), walked as a serpentine (each index runs back on
// every other pass of the next), so that each point neighbours the one before. Held back: the
// points whose indices are all odd, the midpoints between training points.
TrainingDesign grid_design(int m, int n);

// A space-filling design of n points for many actuators, where a grid's n^m is out of reach:
// the 2^m corners of the box (the envelope's) and n - 2^m points of the Halton sequence (radical
// inverses in the first m primes, from its second point: the first is the origin, a corner).
// Every fourth Halton point is held back. Walked from the point nearest `start` (in [0, 1]^m,
// the rest actuation) to the nearest point not yet solved, and so on. Needs n >= 2^m + 4.
TrainingDesign halton_design(int m, int n, const std::vector<double>& start);

}  // namespace hs
