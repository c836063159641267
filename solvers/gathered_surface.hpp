// A surface group of the distributed mesh gathered whole on one rank, for the work that needs
// all of a surface at once (a cavity's closedness, the fluid-weight module). Its faces come in
// the group's order and its nodes in the mesh's order, so the result does not depend on the
// number of ranks. A cavity's surface is small next to the body: gathering it costs little.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <string>
#include <vector>

#include "mesh/distribution.hpp"

namespace hs {

struct GatheredSurface {
  int nodes_per_face = 3;
  std::vector<int64_t> mesh_nodes;    // numbers in the mesh file, ascending
  std::vector<int64_t> global_nodes;  // their PETSc node numbers (dofs 3 n + d)
  std::vector<double> x;              // their reference coordinates, 3 each
  std::vector<int> faces;             // nodes_per_face per face, indices into mesh_nodes
};

// Collective: the whole group on `root` (empty elsewhere), or on every rank for root < 0.
GatheredSurface gather_surface(const Distribution& dist, const std::string& group, int root,
                               MPI_Comm comm);

}  // namespace hs
