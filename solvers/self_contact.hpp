// Self-contact of the body's surfaces (docs/contact.md, "Self-contact"): every node of the
// deck's contact surfaces is kept off every triangle of them that it is not a corner of, by
// the barrier of contact/surface_pair.hpp on the pair of the node and the triangle's feature
// nearest to it (each such feature once per node), and every edge of them off every edge it
// shares no node with, by the edge pairs' barrier there (each pair of edges once). Two bodies
// of one mesh touch the same way.
//
// The surfaces are gathered whole on every rank once (their reference faces and nodes), and
// their current positions at each evaluation (one reduction over 3 doubles a surface node):
// the surface is n^(2/3) of a body of n nodes, and with it whole every rank finds its pairs
// in a tree of the triangles' boxes (contact/box_tree.hpp) with no ghost layers to keep. Each
// rank evaluates the pairs of the nodes it owns, so every pair is counted once on any number
// of ranks; forces reach the triangles' nodes through the same reduction.
//
// A pair couples nodes that share no tetrahedron, so its tangent entries lie outside the
// mesh's pattern: the pairs met so far make a pattern of their own (pattern()), which only
// grows; Problem preallocates the matrix again when it has (Problem::jacobian).
//
// With contact.friction, each pair within dhat at a step's start also holds the lagged
// Coulomb friction of contact/pair_friction.hpp over the step, kept by the rank that owns its
// node or its first edge's first node (accept() and begin_step(), as ObstacleContact's).
#pragma once

#include <mpi.h>

#include <array>
#include <cstdint>
#include <vector>

#include "contact/node_contact.hpp"
#include "contact/pair_friction.hpp"
#include "contact/surface_pair.hpp"
#include "deck/config.hpp"
#include "mesh/distribution.hpp"

namespace hs {

class SelfContact {
 public:
  // constrained(l): whether owned local dof l is prescribed (the tangent leaves its row and
  // column out). Collective.
  SelfContact(const Config& config, const Distribution& dist, const std::vector<char>& constrained,
              const ContactBarrier& barrier, bool project, MPI_Comm comm);

  // One pair: the node and its triangle's feature (2 to 4 surface nodes, the node first), its
  // barrier or (friction) its lagged friction; or (edges) two edges' barrier or friction,
  // nodes 0 and 1 the one edge, 2 and 3 the other.
  struct Pair {
    int count = 0;
    int32_t node[4] = {0, 0, 0, 0};  // surface node indices
    bool friction = false, edges = false;
    PairTerm term;
    // The contact force on the node, or on the first edge (N), against the barrier's push.
    Eigen::Vector3d push() const;
  };
  // The pairs of this rank's nodes at owned displacements u (3 per owned node), the barriers'
  // and the lagged frictions'; false when a node is on a triangle (d = 0). Collective.
  bool pairs(const double* u, std::vector<Pair>& out) const;
  // f += a dE/du over all ranks' pairs, into the owned entries of f; the energy of this rank's
  // pairs into *energy. False as pairs(). Collective.
  bool add_forces(const double* u, double a, double* f, double* energy) const;
  // The pairs the last add_forces found, over all ranks.
  int64_t last_pairs() const { return last_pairs_; }
  // bound += sum_j |d2E/dx_i dx_j| |x_j| at the owned entries: the pairs' part of the
  // residual's round-off (Problem::residual_roundoff), their distances being differences of
  // absolute positions. Collective.
  void add_roundoff(const double* u, double* bound) const;
  // The largest alpha <= 1 of the step du (owned, as u) that keeps every pair at least a tenth
  // of its distance apart: a feature point moves by at most max_k |du_k - du_p| relative to
  // the node, so d(alpha) >= d - alpha max_k |du_k - du_p| (the tree finds the pairs whose
  // swept boxes meet). Collective.
  double step_limit(const double* u, const double* du) const;

  // The tangent's extra pattern: pairs of surface nodes (a, b), sorted, with their PETSc dof
  // indices (negative where constrained).
  const std::vector<std::array<int32_t, 2>>& pattern() const { return pattern_; }
  void pattern_dofs(size_t k, int64_t rows[3], int64_t cols[3]) const;
  // Adds the node pairs of `pairs` missing from the pattern; true (on every rank) when any
  // rank's grew. Collective.
  bool extend_pattern(const std::vector<Pair>& pairs);
  // values (9 per pattern pair, row-major) = the pairs' Hessians. Every pair must be in the
  // pattern (extend_pattern first).
  void fill_tangent(const std::vector<Pair>& pairs, double* values) const;

  // A converged state: the next step's friction is lagged from it once begin_step() is called
  // (until then the forces stay those it converged with). Collective; nothing without friction.
  void accept(const double* u);
  void begin_step();
  bool has_friction() const { return has_friction_; }

  // The contact force surface a exerts on surface b (indices in contact.surfaces) through
  // their pairs' barriers at owned displacements u (N): over the pairs of a node of a and a
  // face of b, the node's dE/dx, less the same over those of a node of b and a face of a.
  // A face in two surfaces belongs to the first listed. Collective.
  std::array<double, 3> force_between(const double* u, int a, int b) const;
  // Its derivative, rows[d][i] = dF_d/du_i at the owned entries (3 per owned node, set here),
  // from the pairs' Hessians unprojected; 0 returned. Where no pair of a and b acts, the gap
  // between them (their nearest node and face) is returned instead, and the rows are a unit
  // spring across it, +-n n^T on the node's move less its nearest point's (n from that point
  // to the node), whose force grows as the gap closes. Collective.
  double force_rows_between(const double* u, int a, int b, double* rows[3]) const;

  struct Totals {
    int64_t pairs = 0;    // within dhat, over all ranks
    double force = 0;     // the sum of the pairs' contact force magnitudes (N)
    double friction = 0;  // the sum of the lagged pairs' friction force magnitudes (N)
    double min_gap = 0;   // the smallest node-triangle distance (m)
  };
  Totals totals(const double* u) const;  // collective
  // Per owned node (num_owned of them), for the output: `gap`, the smallest distance of its
  // pairs, dhat where it has none (and off the surfaces); `pressure`, the size of the pairs'
  // force on it over its share of the surfaces' area, 0 off them. Collective.
  // `friction`: the friction's traction on the node (Pa, 3 per node), the pairs' friction forces
  // on it over its area, with contact.friction.
  struct NodeValues {
    std::vector<double> gap, pressure, friction;
  };
  NodeValues node_values(const double* u, int64_t num_owned) const;
  int64_t num_nodes() const { return static_cast<int64_t>(global_.size()); }
  const ContactBarrier& barrier() const { return barrier_; }

 private:
  // Every surface node's displacement (3 each) from the owned displacements.
  std::vector<double> positions(const double* u) const;
  // Every surface node's current position (3 each): positions(u) + its reference.
  std::vector<double> current(const double* u) const;
  // Every pair within dhat of this rank's nodes at positions x, as visit(nodes, count, face,
  // the barrier's term, its Hessian projected with `project`).
  template <class Visit>
  bool each_pair(const std::vector<double>& x, bool project, Visit&& visit) const;
  // Every pair of edges within dhat at positions x with an edge of this rank's, as
  // visit(nodes, edge, other edge, the barrier's term).
  template <class Visit>
  bool each_edge_pair(const std::vector<double>& x, bool project, Visit&& visit) const;
  // +1 for edge e of surface a and edge f of b, -1 the other way round, else 0.
  int edge_side(int32_t e, int32_t f, int a, int b) const;
  // +1 for a pair of node p of surface a and face f of b, -1 for p of b and f of a, else 0
  // (force_between's sign of the node's dE/dx).
  int side(int32_t p, int32_t f, int a, int b) const;
  // No node may start within dhat of a triangle it is not a corner of, no edge within dhat of
  // an edge it shares no node with. Collective.
  void check_start(const std::string& deck) const;

  MPI_Comm comm_;
  ContactBarrier barrier_;
  bool project_ = false;
  mutable int64_t last_pairs_ = 0;
  std::vector<int64_t> global_;                // per surface node: its PETSc node number
  std::vector<double> reference_;              // per surface node: its reference position
  std::vector<int64_t> owned_;                 // per surface node: its owned local index or -1
  std::vector<char> constrained_;              // per surface node: 3 flags
  std::vector<double> area_;                   // per surface node: its share of the area (m^2)
  std::vector<std::array<int32_t, 3>> faces_;  // surface node indices
  int flat_per_face_ = 1;  // faces_ per mesh face, consecutive: 1 (P1) or 4 (P2)
  std::vector<std::vector<int32_t>> faces_of_;  // per surface node: the faces it is a corner of
  std::vector<int32_t> mine_;                   // the surface nodes this rank owns
  std::vector<std::array<int32_t, 2>> edges_;   // surface node indices, the smaller first
  std::vector<double> edge_area_;               // per edge: a third of its triangles' areas
  std::vector<double> edge_length2_;            // per edge: its squared length at rest
  std::vector<uint64_t> edge_surfaces_;         // per edge: its triangles' surfaces, one bit each
  std::vector<int32_t> my_edges_;               // the edges whose first node this rank owns
  std::vector<std::array<int32_t, 2>> pattern_;
  // mu between node p and face f: the largest over p's surfaces of the coefficient between
  // that surface and f's (contact.friction, or contact.friction_between's for the pair).
  double friction(int32_t p, int32_t f) const;
  // mu between edges e and f: the largest over their surfaces' pairs.
  double edge_friction(int32_t e, int32_t f) const;
  int num_surfaces_ = 0;                 // the deck's contact.surfaces
  std::vector<int> face_surface_;        // per face: its surface (index in the deck's list)
  std::vector<uint64_t> node_surfaces_;  // per surface node: its surfaces, one bit each
  std::vector<double> friction_;         // per pair of surfaces (row-major): mu
  bool has_friction_ = false;
  double slip_ = 0;                   // eps_v (m)
  std::vector<PairFrictionLag> lag_;  // sorted by begin_step's key
  std::vector<double> accepted_;      // positions of a state not lagged yet
};

}  // namespace hs
