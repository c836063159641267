// The reduced-order model's file (docs/reduced_models.md), written by `hydrosoft reduce` and
// read by a control run with control.reduced_model. One HDF5 file:
//   attributes of /: format = "hydrosoft reduced model", version = 1, model = JSON text (what
//     the model was trained on and how well it did: ReducedModel's scalars and lists)
//   /basis      (3 N) x k float64: the POD modes, row 3 n + d for dof d of mesh node n
//   /elements   E int64: the hyper-reduction's tetrahedra (numbers in the mesh file)
//   /weights    E float64: their ECSW weights (> 0)
//   /patches    P int64: the hyper-reduction's node patches (mesh node numbers), where the
//               body runs the nodal-pressure element: each node's volumetric term
//   /patch_weights  P float64: their ECSW weights (> 0)
//   /training_actuations  S x m float64: the training samples' actuations
//   /training_states      S x k float64: their snapshots' reduced coordinates (Phi^T u)
// The file is written whole or not at all: into "<path>.tmp", renamed once closed.
#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace hs {

struct ReducedModel {
  // What it belongs to: the mesh (nodes, tetrahedra, order, a checksum of the reference
  // coordinates) and the physics of the deck it was trained on (materials, gravity, cavities,
  // cables, boundary: the deck's printed sections), which a run's must match.
  int64_t nodes = 0, tets = 0;
  int order = 1;
  double coordinate_checksum = 0;
  std::string physics;
  std::string deck;  // the training deck's name (for the reader only)
  // The actuators (constraint names, in the control section's order) and the training
  // envelope: each one's multiplier range sampled.
  std::vector<std::string> actuators;
  std::vector<double> lower, upper;
  Eigen::MatrixXd basis;
  std::vector<int64_t> elements;
  std::vector<double> weights;
  std::vector<int64_t> patches;  // nodes
  std::vector<double> patch_weights;
  // The training samples: each one's actuation (m) and reduced coordinates (k), where a
  // reduced Newton far from the last answer starts.
  Eigen::MatrixXd training_actuations, training_states;
  // The training's report (summary.json's `reduction`): sizes, criteria, errors, times.
  nlohmann::json report;
};

// Throws SolveError naming the file when it cannot be written.
void write_reduced_model(const std::string& path, const ReducedModel& model);
// Throws InputError naming the file and the reason: missing, not HDF5, not a reduced model,
// a dataset of the wrong shape, non-finite or out-of-range values.
ReducedModel read_reduced_model(const std::string& path);

// A checksum of reference coordinates (3 per node, mesh order) that a renumbered, moved or
// other mesh does not share: sum_n (n mod 97 + 1) (x + 2 y + 3 z).
double coordinate_checksum(const std::vector<double>& x);

}  // namespace hs
