// A cable actuator: a path of material points x_1 .. x_P of the body (each a point of a
// tetrahedron, x_i = sum_a N_a (X_a + u_a)) and, optionally, a fixed pull point x_{P+1} in
// space after the last one (the motor). Its length is
//   L(u) = sum_i |x_{i+1} - x_i|   (the pull point's segment included),
// and a tension T >= 0 puts the force -T dL/dx_i on each point: the ends are pulled along
// the cable, a point in between (an eyelet) along the sum of its two unit directions, as a
// frictionless cable would. In the cavity system a cable is one more constraint with
// multiplier T and "volume" -L, so that its column g = -dL/du is the force of a unit
// tension and the shortening (pull) plays the volume growth. docs/control.md has the rest.
#pragma once

#include <petscmat.h>
#include <petscvec.h>

#include <array>
#include <string>
#include <vector>

#include "deck/config.hpp"
#include "solvers/problem.hpp"

namespace hs {

class CablePath {
 public:
  // Collective. Throws InputError naming the deck, the cable and the point when a point
  // lies outside the mesh.
  CablePath(const CableConfig& config, Problem& problem, const std::string& deck_path);
  CablePath(const CablePath&) = delete;
  CablePath& operator=(const CablePath&) = delete;

  // Current positions of the cable's points (3 per point, every rank; collective).
  std::vector<double> positions(Vec u) const;
  double length(Vec u) const;
  // g = -dL/du: the nodal forces of a unit tension (zero on no dof but the points' nodes).
  void pull_direction(Vec u, Vec g) const;
  // T d2L/du2: the stiffness of a tension T turning with the path (per segment
  // T (I - e e^T) / l between its two points), Dirichlet rows and columns left out. Sets the
  // problem's coupling blocks that the constructor registered (one per segment, rank 0), so
  // the next tangent holds it. Collective.
  void set_stiffness(Vec u, double T, Problem& problem) const;

  // The polyline the cable follows on configuration u: its material points, then the pull
  // point if it has one (collective).
  std::vector<std::array<double, 3>> path(Vec u) const { return path(positions(u)); }
  // g = sum_i f_i . x_i(u): nodal forces from forces f_i on the material points (3 each).
  void distribute(const std::vector<double>& f, Vec g) const;
  // The material points: their element's dofs (3 per node, -1 where constrained) and the
  // nodes' shape-function values at the point.
  size_t points() const { return dofs_.size(); }
  const std::vector<PetscInt>& dofs(size_t i) const { return dofs_[i]; }
  const std::vector<double>& shape(size_t i) const { return shape_[i]; }

 private:
  std::vector<std::array<double, 3>> path(const std::vector<double>& x) const;

  CableConfig config_;
  std::vector<double> reference_;  // 3 per point
  VecArray rows_;                  // 3 per point: the point's coordinate as a row over u
  // Per point: the global dofs of its element's nodes (3 per node, -1 where constrained)
  // and the nodes' shape-function values there.
  std::vector<std::vector<PetscInt>> dofs_;
  std::vector<std::vector<double>> shape_;
  std::vector<int> couplings_;  // rank 0: the problem's coupling block of each segment
};

}  // namespace hs
