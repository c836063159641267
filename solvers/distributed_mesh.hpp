// Each rank's piece of the deck's mesh, the way a run gets it (docs/architecture.md, "The
// distributed mesh"): a .h5 mesh (hydrosoft mesh DECK) is read in blocks by every rank; a
// .msh or .geo is loaded by rank 0 through gmsh and sent out in blocks. Either way the
// tetrahedra are partitioned in parallel by PTScotch (PETSc's MatPartitioning on their dual
// graph) and moved to their parts (distribute_slabs); no rank ever holds the whole mesh
// unless rank 0 had to load a .msh or .geo.
#pragma once

#include <mpi.h>

#include <memory>
#include <vector>

#include "deck/config.hpp"
#include "mesh/distribution.hpp"
#include "mesh/mesh_slab.hpp"

namespace hs {

struct MeshLoadTimes {
  double read_s = 0, partition_s = 0, distribute_s = 0;
};

// Collective. Throws InputError on every rank for a bad mesh (naming the file) and for more
// tetrahedra than cfg.max_elements. `solver`: the deck's options for the partitioner.
Distribution load_distributed_mesh(const MeshConfig& cfg, MPI_Comm comm,
                                   MeshLoadTimes* times = nullptr,
                                   const SolverConfig& solver = SolverConfig{});

// Collective: the whole mesh on rank 0 (null elsewhere), loaded or meshed through gmsh; its
// units warning, if any, on standard error. A failure is thrown on every rank.
std::unique_ptr<Mesh> load_mesh_on_rank_zero(const MeshConfig& cfg, MPI_Comm comm);

// Collective: the part (rank) of each of the slab's tetrahedra, balanced, with few faces
// cut. The same mesh on the same ranks splits the same way when Scotch runs one thread per
// process (use_one_scotch_thread; with several its search is not repeatable). The
// partitioner's own options (prefix hs_partition_, composed from `solver` and the command line
// as a solver object's are): -mat_partitioning_type chooses another of PETSc's partitioners.
std::vector<int> partition_slab(const MeshSlab& slab, MPI_Comm comm,
                                const SolverConfig& solver = SolverConfig{});

// Before the first partition (main, and the tests' main): Scotch runs one thread per process,
// unless SCOTCH_PTHREAD_NUMBER is set. The ranks already fill the cores; Scotch's default,
// a thread per core in every rank, oversubscribes them (250 s instead of seconds for 1.9M
// tetrahedra on 16 ranks) and makes its partitions differ from run to run.
void use_one_scotch_thread();

}  // namespace hs
