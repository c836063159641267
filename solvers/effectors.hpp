// End effectors of the inverse controller: material points of the body (a mesh node named
// by a point group, or any point inside the mesh located in its tetrahedron) whose position
// x_e(u) = sum_a N_a(xi_e) (X_a + u_a) is linear in the displacements. Each controlled
// direction d of effector e is one row of J_e: a distributed vector with N_a at the dofs
// (a, d), zero on Dirichlet dofs, so that J_e du = row . du.
// Or the contact force the body exerts on an obstacle, F_o(u) = sum over the contact nodes of
// the barrier's force (ObstacleContact; or those of some contact surfaces only, one finger's),
// which is not linear: its rows are dF_o/du at the configuration last given to linearize(),
// the per-obstacle barrier Hessians. Or the force one contact surface exerts on another
// through self-contact's pairs (SelfContact::force_between), its rows the pairs' Hessians.
#pragma once

#include <petscvec.h>

#include <array>
#include <string>
#include <vector>

#include "deck/config.hpp"
#include "solvers/problem.hpp"

namespace hs {

// A material point: the nodes around it (PETSc node numbers), their shape-function values
// there, whether each of their dofs is free (not held by a Dirichlet condition), and its
// reference position. The same on every rank.
struct MaterialPoint {
  std::vector<int64_t> nodes;
  std::vector<double> N;
  std::vector<char> free_dofs;  // 3 per node
  std::array<double, 3> X{};
};

// Collective: the point at X (reference coordinates) in the tetrahedron that holds it, or
// false when X lies outside the mesh. Located by the barycentric coordinates of the corners
// (straight-sided tetrahedra; for P2 meshes the corner simplex, exact where the edges are
// straight); on a shared face or edge, the most inside one, over every rank's tetrahedra.
bool locate(const Problem& problem, const std::array<double, 3>& X, MaterialPoint& point);

// Collective: the node of a point group that holds exactly one (check_groups makes sure).
MaterialPoint group_point(const Problem& problem, const std::string& group);

// The three coordinates of the material point sum_a N_a (X_a + u_a) as rows over u:
// distributed vectors with N_a at the dofs (a, d), appended to `rows` (collective; `nodes` are
// PETSc node numbers).
void append_point_rows(Problem& problem, const std::vector<int64_t>& nodes,
                       const std::vector<double>& N, VecArray& rows);

class Effectors {
 public:
  // Collective. Throws InputError naming the effector when its point group does not hold
  // exactly one node or its position lies outside the mesh.
  Effectors(const Config& config, Problem& problem);
  Effectors(const Effectors&) = delete;
  Effectors& operator=(const Effectors&) = delete;

  int size() const { return static_cast<int>(names_.size()); }
  int index(const std::string& name) const;  // -1 if unknown
  const std::string& name(int e) const { return names_[e]; }
  const EffectorConfig& config(int e) const { return configs_[e]; }
  // Whether effector e is a contact force (N: on an obstacle, or between two contact
  // surfaces) rather than a position (m).
  bool is_force(int e) const { return obstacle_[e] >= 0 || between_[e][0] >= 0; }
  // The unit of effector e's values: "m" or "N".
  const char* unit(int e) const { return is_force(e) ? "N" : "m"; }
  // Current positions (contact forces for force effectors) on configuration u (3 per
  // effector, every rank). Collective.
  std::vector<double> positions(Vec u) const;
  // The force effectors' rows at configuration u (positions' rows do not change).
  // Collective.
  void linearize(Vec u);
  // After linearize: 0 when force effector e's nodes touch its obstacle, else the gap of the
  // nearest one, whose rows are then a unit spring across it (Problem::contact_force_rows).
  double approach_gap(int e) const { return approach_gap_[e]; }
  // A force on an obstacle: the obstacle's index (else -1) and the contact nodes it counts
  // (per local node; null: every contact node).
  int obstacle(int e) const { return obstacle_[e]; }
  const std::vector<char>* contact_nodes(int e) const { return only(e); }
  // Row of J_e for effector e, direction d.
  Vec row(int e, int d) const { return rows_[3 * e + d]; }

 private:
  const std::vector<char>* only(size_t e) const;  // null: every contact node

  Problem& problem_;
  std::vector<std::string> names_;
  std::vector<EffectorConfig> configs_;
  std::vector<int> obstacle_;  // per effector: the obstacle's index, -1 for a position
  // per effector: `between`'s surfaces (indices in contact.surfaces), -1 otherwise
  std::vector<std::array<int, 2>> between_;
  // Per effector with `surfaces`: its contact nodes (per local node), else empty.
  std::vector<std::vector<char>> only_;
  std::vector<double> approach_gap_;
  std::vector<double> reference_;  // 3 per effector
  VecArray rows_;                  // 3 per effector
};

}  // namespace hs
