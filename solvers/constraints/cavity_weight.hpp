// The liquid's weight on one cavity's walls, on the deformed cavity, by the fluid-weight
// module (cuda/: the paper's column method on CPU or CUDA, or the closed-form hydrostatic
// pressure). The cavity's surface is gathered to one owning rank, which runs the module and
// adds the nodal forces into a distributed vector (docs/cavities.md, "Distributed runs").
#pragma once

#include <petscvec.h>

#include <fluidweight/fluidweight.hpp>
#include <memory>
#include <string>
#include <vector>

#include "deck/config.hpp"
#include "mesh/distribution.hpp"
#include "solvers/gathered_surface.hpp"
#include "solvers/petsc_handle.hpp"

namespace hs {

// The flat triangles the fluid-weight module sees for a cavity's walls, and how their
// vertices (the points) follow the walls' nodes. Tri3 faces are the triangles themselves,
// their points the nodes. A Tri6 face is its quadratic map sampled at the vertices of
// n x n sub-triangles (n = 2: the four through its edge nodes, the points the nodes), each
// point a fixed combination of the face's six nodes (their shape functions there) and shared
// with the neighbouring face where they meet. Flat sub-triangles leave out the curved face's
// bulge, which shrinks as 1/n^2 (docs/cavities.md, "Curved walls"); forces at the points
// reach the nodes through the same shape functions (the transpose: the same virtual work).
struct WallTriangulation {
  struct Term {
    int point, node;
    double weight;
  };
  int num_points = 0;
  std::vector<int> triangles;  // 3 per triangle, indices into the points
  std::vector<Term> terms;     // point = sum of weight * node over its terms

  // The points' coordinates from the nodes' (3 each).
  void points_of(const std::vector<double>& nodes, std::vector<double>& points) const;
  // The nodes' forces from the points' (3 each), for num_nodes nodes.
  void node_forces(const std::vector<double>& points, size_t num_nodes,
                   std::vector<double>& nodes) const;
};

// n: the sub-triangles along an edge of a Tri6 face (>= 2); Tri3 faces ignore it.
WallTriangulation wall_triangulation(const GatheredSurface& surface, int n);

class CavityWeight {
 public:
  // Collective. `owner` is the rank that runs the fluid-weight module for this cavity.
  CavityWeight(const Distribution& dist, const CavityConfig& cavity,
               const std::array<double, 3>& gravity, int owner, MPI_Comm comm);
  CavityWeight(const CavityWeight&) = delete;
  CavityWeight& operator=(const CavityWeight&) = delete;

  // W += nodal weights of the liquid filling the cavity on configuration u (global vector of
  // displacements), under gravity * load_factor (the weights are linear in |g|). Collective;
  // W is assembled on return.
  void add_weight(Vec u, double load_factor, Vec W);

  // Of the last add_weight (the same on every rank): |sum of the nodal forces|, the volume the
  // module measured (column volume, or |signed volume| for hydrostatic), and its time.
  double total_weight() const { return total_weight_; }
  // The column methods' jump in the weights (fluidweight::Result::column_weight, times the
  // load factor) at the last call; 0 in closed form.
  double column_weight() const { return column_weight_; }
  double measured_volume() const { return volume_; }
  double seconds() const { return seconds_; }
  const char* device() const;
  int owner() const { return owner_; }

 private:
  MPI_Comm comm_;
  int rank_ = 0, owner_ = 0;
  double density_ = 0, gravity_norm_ = 0;
  fluidweight::Options options_;
  WallTriangulation walls_;            // owner: the module's triangles on the surface nodes
  std::vector<double> reference_;      // owner: reference positions of the surface nodes
  std::vector<double> positions_;      // owner: current positions
  std::vector<double> points_;         // owner: current positions of the triangles' points
  std::vector<PetscInt> global_dofs_;  // owner: PETSc dofs of the surface nodes
  std::unique_ptr<fluidweight::Context> context_;  // owner only
  VecHandle surface_u_;  // sequential, 3 per surface node on the owner, empty elsewhere
  VecScatterHandle gather_;
  double total_weight_ = 0, volume_ = 0, seconds_ = 0, column_weight_ = 0;
};

}  // namespace hs
