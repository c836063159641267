// The parallel way of a run (partition_slab, distribute_slabs) from a mesh every rank holds:
// tests keep the whole mesh as the reference they check a distributed result against.
#pragma once

#include <petscsys.h>

#include "mesh/mesh_distribute.hpp"
#include "solvers/distributed_mesh.hpp"

namespace hs_test {

inline hs::Distribution distribute_whole(const hs::Mesh& mesh) {
  int rank, size;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  const hs::MeshSlab slab = hs::slab_of(mesh, rank, size);
  return hs::distribute_slabs(slab, hs::partition_slab(slab, PETSC_COMM_WORLD), PETSC_COMM_WORLD);
}

}  // namespace hs_test
