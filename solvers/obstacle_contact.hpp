// Contact of the body's surfaces with rigid obstacles (docs/contact.md): every owned node of
// the deck's contact surfaces carries the barrier energy of contact/node_contact.hpp,
// weighted by its share of the surfaces' reference area. Node by node, so no search and no
// communication in the residual or the tangent (3x3 blocks on the diagonal), and each node
// counted by the rank that owns it: the same sums on any number of ranks.
#pragma once

#include <mpi.h>
#include <petscvec.h>

#include <array>
#include <string>
#include <vector>

#include "contact/friction.hpp"
#include "contact/node_contact.hpp"
#include "deck/config.hpp"
#include "mesh/distribution.hpp"
#include "solvers/node_pair_blocks.hpp"

namespace hs {

// The barrier's reach and stiffness: the deck's contact.distance and contact.stiffness, or
// from the mesh's bounding box and the stiffest material (docs/contact.md). Collective.
ContactBarrier contact_barrier_of(const Config& config, const std::vector<double>& X,
                                  MPI_Comm comm);

class ObstacleContact {
 public:
  // `work`: a ghosted vector of the problem's layout, used once to sum the nodes' areas
  // over the ranks whose faces share them. The barrier's unset parameters come from the
  // mesh's bounding box and the stiffest material (docs/contact.md). Collective.
  ObstacleContact(const Config& config, const Distribution& dist, const std::vector<double>& X,
                  Vec work, MPI_Comm comm);

  // r += a dE/du at the owned contact nodes (u, r: the local forms); the energy of those
  // nodes in *energy. False when a node is on or inside an obstacle (inside() names it).
  bool add_forces(const double* u, double s, double a, double* r, double* energy);
  // Each owned contact node's barrier at u (its exact Hessian), in nodes()'s order: for a
  // reduced model, which projects them itself. False when a node is on or inside an obstacle.
  bool node_terms(const double* u, double s, std::vector<NodeContact>& terms) const;
  const std::vector<int32_t>& nodes() const { return nodes_; }
  // The barrier's Hessians into the tangent's node-pair blocks.
  void add_tangent(const double* u, double s, const NodePairBlocks& pairs, double* values) const;
  // The largest fraction alpha <= 1 of a step du (owned values, 3 per node, as u) that keeps
  // every contact node at least a tenth of its gap outside every obstacle (step_bound of
  // contact/obstacle.hpp). On this rank.
  double step_limit(const double* u, const double* du, double s) const;
  // The force the body's contact nodes exert on obstacle o (with friction, as totals()),
  // those with only[n] set where `only` (per local node) is given; on this rank.
  Eigen::Vector3d force_on(const double* u, double s, int o, const std::vector<char>* only) const;
  // Its derivative with respect to the displacements, as three rows (d F_o,x / du, ...):
  // rows[d] holds the owned values, 3 per node, set at those contact nodes (the exact
  // per-obstacle Hessians) and untouched elsewhere. On this rank.
  void force_rows(const double* u, double s, int o, const std::vector<char>* only,
                  double* const rows[3]) const;
  // Of those contact nodes, the one nearest to obstacle o: its local number (-1 when this
  // rank has none), its gap and the obstacle's outward normal there. On this rank.
  struct Nearest {
    int32_t node = -1;
    double gap = 0;
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  };
  Nearest nearest(const double* u, double s, int o, const std::vector<char>* only) const;
  // The index of an obstacle a node was found inside by the last add_forces on this rank,
  // or -1.
  int inside() const { return inside_; }
  // A converged state at load factor s: the start of the next step, whose friction is lagged
  // from here (friction.hpp) once begin_step() is called; until then the forces stay those
  // the state converged with (its output). The undeformed body at s = 0 before the first.
  void accept(const double* u, double s);
  void begin_step();
  bool has_friction() const { return has_friction_; }

  struct Totals {
    std::vector<std::array<double, 3>> force;  // per obstacle: the body's force on it (N)
    std::vector<double> area;                  // per obstacle: reference area within dhat (m^2)
    double min_gap = 0;                        // the smallest gap of any contact node (m)
    double loaded_gap = 0;  // with held forces: the largest |gap| of a node holding one (m)
  };
  // Over all ranks. Collective.
  Totals totals(const double* u, double s) const;

  // Per owned node (the problem's rows): the gap to the nearest obstacle (m, every node), the
  // contact pressure (Pa: the barrier's normal forces over the node's area; 0 off the contact
  // surfaces) and the friction traction on the body (Pa, 3 per node).
  struct NodeValues {
    std::vector<double> gap, pressure, friction;
  };
  NodeValues node_values(const double* u, double s, int64_t num_owned) const;

  // control.contact_forces: qp (docs/control.md, "Contact forces in the QP"): the barrier
  // gives way to normal forces that the controller holds and sets, one per contact node, each
  // a constant load `force` n on the body (n the obstacle's outward normal, fixed within a
  // step), so that the residual has no contact stiffness and the forces, totals and fields
  // report those loads. In nodes()'s order.
  struct Held {
    int obstacle = -1;
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    double force = 0;  // N, >= 0
  };
  // Switches to held forces, each node's the barrier's normal force at u.
  void hold_forces(const double* u, double s);
  bool holds_forces() const { return !held_.empty(); }
  std::vector<Held>& held() { return held_; }
  // Each held force's normal turned to the obstacle's where its node is at u.
  void turn_held_normals(const double* u, double s);
  // The contact nodes (index in nodes()) within `reach` of an obstacle at u, with the nearest
  // obstacle, the gap to it and its outward normal there; a node holding a force keeps its
  // obstacle and normal. On this rank.
  struct Candidate {
    int index = -1;
    int obstacle = -1;
    double gap = 0;
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  };
  std::vector<Candidate> candidates(const double* u, double s, double reach) const;

  const std::vector<ObstacleShape>& obstacles() const { return obstacles_; }
  const ContactBarrier& barrier() const { return barrier_; }
  int64_t num_nodes() const { return num_nodes_; }  // over all ranks

 private:
  Eigen::Vector3d position(const double* u, int32_t node) const;
  // Node i's barrier and friction at position x, load factor s.
  NodeContact evaluate(size_t i, const Eigen::Vector3d& x, double s, bool project) const;
  NodeContact held_load(size_t i, const Eigen::Vector3d& x) const;
  void check_start(const std::string& deck) const;  // collective; throws InputError

  MPI_Comm comm_;
  std::vector<ObstacleShape> obstacles_;
  ContactBarrier barrier_;
  // The tangent's Hessians projected onto the semi-definite ones for CG (the gamg preset),
  // which needs a definite matrix; exact for the direct solvers, which keep Newton quadratic
  // (docs/contact.md: 70 against 142 iterations on input/finger_press.yaml).
  bool project_ = false;
  const std::vector<double>& X_;
  std::vector<int32_t> nodes_;  // the owned local nodes of the contact surfaces
  std::vector<double> area_;    // each one's share of the surfaces' area (m^2)
  int64_t num_nodes_ = 0;
  bool has_friction_ = false;
  double slip_ = 0;                        // eps_v (m)
  std::vector<FrictionLag> lag_;           // per contact node, with friction
  std::vector<Eigen::Vector3d> accepted_;  // the last accepted positions, not yet lagged
  double accepted_s_ = 0;
  int inside_ = -1;
  std::vector<Held> held_;  // with held forces: one per contact node
};

}  // namespace hs
