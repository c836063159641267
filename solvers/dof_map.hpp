// The degrees of freedom one rank works on: 3 per local node (owned nodes first, then ghosts,
// in the numbering of hs::Distribution), their PETSc global indices, the ghosted vectors, and
// the Dirichlet data. Constrained dofs keep their rows in the system (R_D = u_D - g_D(s));
// element and face blocks name them -1, so that the assembly drops their entries.
#pragma once

#include <petscvec.h>

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "deck/config.hpp"
#include "mesh/distribution.hpp"
#include "mesh/mesh.hpp"

namespace hs {

// The displacement at reference point X and load factor s that Dirichlet conditions marked
// exact take (the run sets it from the deck's exact solution).
using ExactDirichlet =
    std::function<std::array<double, 3>(const std::array<double, 3>& X, double s)>;

class DofMap {
 public:
  // Throws InputError for a condition marked exact when `exact` is empty.
  DofMap(const Config& config, const Distribution& dist, ExactDirichlet exact);

  Vec create_vector(MPI_Comm comm) const;  // ghosted, block size 3, zeroed
  int64_t num_owned_dofs() const { return 3 * num_owned_; }
  // Reference coordinates of the local nodes (3 each).
  const std::vector<double>& reference() const { return X_; }

  // PETSc indices of the dofs of n local nodes (3 each), -1 for constrained ones.
  void indices(const int32_t* nodes, int n, PetscInt* idx) const;
  bool constrained(int64_t local_dof) const { return constrained_[local_dof]; }
  PetscInt global(int64_t local_dof) const { return global_[local_dof]; }

  // A translation added to a boundary group's prescribed values (a state's `move`), on the
  // components it prescribes; `moved` gives the group's present one.
  void set_move(const std::string& group, const std::array<double, 3>& by);
  std::array<double, 3> moved(const std::string& group) const;
  // Every group's translation (in the order of the deck's boundary groups; empty when none
  // moved yet), and the same set back.
  using Moves = std::vector<std::array<double, 3>>;
  const Moves& moves() const { return moves_; }
  void set_moves(const Moves& moves) { moves_ = moves; }

  // The prescribed value of a constrained dof at load factor s (with its group's move).
  double prescribed_value(int64_t local_dof, double s) const;
  // Sets the constrained dofs of u to their values at s (owned entries).
  void apply(Vec u, double s) const;
  // R_D = u_D - g_D(s) on the constrained rows of R (owned entries).
  void set_rows(Vec u, double s, Vec R) const;
  // Zeroes the constrained dofs of v (owned entries).
  void zero(Vec v) const;

  // The deck's boundary groups, each once, in the deck's order, and the index among them of
  // the first group that constrains a dof (reactions are summed per group).
  const std::vector<std::string>& groups() const { return groups_; }
  int group_of(int64_t local_dof) const { return group_of_[local_dof]; }

 private:
  int64_t num_owned_ = 0;
  const std::vector<double>& X_;  // the distribution's: it outlives the map
  std::vector<PetscInt> global_, ghost_blocks_;
  std::vector<char> constrained_, scaled_, from_exact_;  // per local dof
  std::vector<double> prescribed_;                       // per local dof, at full load
  std::vector<std::string> groups_;
  std::vector<int> group_of_;  // per local dof: index in groups_, -1 if not constrained
  std::vector<std::array<double, 3>> moves_;  // per group
  // per local dof: the group of the first entry that prescribes it (its move's), -1 if none
  std::vector<int> moved_by_;
  ExactDirichlet exact_;
};

}  // namespace hs
