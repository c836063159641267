#include "solvers/distributed_mesh.hpp"

#include <petscmat.h>

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <stdexcept>

#include "common/error.hpp"
#include "common/exchange.hpp"
#include "common/interrupt.hpp"
#include "mesh/gmsh_io.hpp"
#include "mesh/mesh_checks.hpp"
#include "mesh/mesh_distribute.hpp"
#include "mesh/mesh_h5.hpp"
#include "solvers/petsc_check.hpp"
#include "solvers/petsc_handle.hpp"
#include "solvers/solver_options.hpp"

// Scotch's generator advances with every partition in a process: reset before each one, a
// graph splits the same way each time. (Declared here: scotch.h is not needed for one call.)
extern "C" void SCOTCH_randomReset(void);

namespace hs {
namespace {

// As the deck parser and load_mesh read extensions: in any case.
bool is_h5(const std::string& file) {
  std::string extension = std::filesystem::path(file).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension == ".h5";
}

}  // namespace

std::unique_ptr<Mesh> load_mesh_on_rank_zero(const MeshConfig& cfg, MPI_Comm comm) {
  std::unique_ptr<Mesh> mesh;
  on_rank_zero(comm, [&] {
    try {
      mesh = std::make_unique<Mesh>(load_mesh(cfg));
    } catch (const Interrupted&) {  // a signal stopped gmsh: every rank stops below, together
      return;
    }
    const std::string warning = units_warning(*mesh, cfg.file);
    if (!warning.empty()) std::cerr << "hydrosoft: warning: " << warning << std::endl;
  });
  stop_if_interrupted(comm);
  return mesh;
}

void use_one_scotch_thread() { setenv("SCOTCH_PTHREAD_NUMBER", "1", 0); }

std::vector<int> partition_slab(const MeshSlab& slab, MPI_Comm comm, const SolverConfig& solver) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  const int64_t n = slab.slab_tets();
  if (size == 1) return std::vector<int>(n, 0);
  if (slab.num_tets < size)
    throw InputError("the mesh has " + std::to_string(slab.num_tets) +
                     " tetrahedra, fewer than the " + std::to_string(size) +
                     " parts (MPI ranks) asked for");
  const DualGraph graph = dual_graph(slab, comm);
  // MatCreateMPIAdj takes ownership of the PetscMalloc'd rows.
  PetscInt *ia = nullptr, *ja = nullptr;
  HS_PETSC(PetscMalloc1(n + 1, &ia));
  HS_PETSC(PetscMalloc1(graph.neighbours.size(), &ja));
  for (int64_t i = 0; i <= n; ++i) ia[i] = static_cast<PetscInt>(graph.offsets[i]);
  for (size_t k = 0; k < graph.neighbours.size(); ++k)
    ja[k] = static_cast<PetscInt>(graph.neighbours[k]);
  MatHandle adjacency;
  HS_PETSC(MatCreateMPIAdj(comm, static_cast<PetscInt>(n), static_cast<PetscInt>(slab.num_tets), ia,
                           ja, nullptr, adjacency.out()));
  const SolverOptions options(kPartitionPrefix, solver, {}, SolverOptions::Reach::every_object);
  MatPartitioningHandle partitioning;
  HS_PETSC(MatPartitioningCreate(comm, partitioning.out()));
  const auto object = reinterpret_cast<PetscObject>(partitioning.get());
  options.attach(object);
  HS_PETSC(PetscObjectSetOptionsPrefix(object, kPartitionPrefix));
  HS_PETSC(MatPartitioningSetAdjacency(partitioning, adjacency));
  HS_PETSC(MatPartitioningSetType(partitioning, MATPARTITIONINGPTSCOTCH));
  HS_PETSC(MatPartitioningSetFromOptions(partitioning));
  IsHandle parts;
  SCOTCH_randomReset();
  HS_PETSC(MatPartitioningApply(partitioning, parts.out()));
  const PetscInt* p;
  HS_PETSC(ISGetIndices(parts, &p));
  std::vector<int> part(p, p + n);
  HS_PETSC(ISRestoreIndices(parts, &p));
  return part;
}

Distribution load_distributed_mesh(const MeshConfig& cfg, MPI_Comm comm, MeshLoadTimes* times,
                                   const SolverConfig& solver) {
  const double t0 = MPI_Wtime();
  // From a .msh or .geo, rank 0 keeps the whole mesh only until the blocks are sent. An .h5
  // is checked in blocks as it is read (read_mesh_h5), the element limit before reading.
  MeshSlab slab = is_h5(cfg.file) ? read_mesh_h5(cfg.file, cfg.max_elements, comm)
                                  : scatter_mesh(load_mesh_on_rank_zero(cfg, comm).get(), 0, comm);
  slab.file = cfg.file;
  if (slab.num_tets > cfg.max_elements)
    throw InputError(
        cfg.file + ": " + std::to_string(slab.num_tets) +
        " tetrahedra, more than mesh.max_elements = " + std::to_string(cfg.max_elements));
  const double t1 = MPI_Wtime();
  const std::vector<int> part = partition_slab(slab, comm, solver);
  const double t2 = MPI_Wtime();
  Distribution d = distribute_slabs(slab, part, comm);
  if (times) {
    times->read_s = t1 - t0;
    times->partition_s = t2 - t1;
    times->distribute_s = MPI_Wtime() - t2;
  }
  return d;
}

}  // namespace hs
