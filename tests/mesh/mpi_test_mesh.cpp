// load_mesh_replicated on every rank: the broadcast copy equals what each rank gets by
// meshing the same source itself; a bad mesh stops all ranks with the root's message; the
// distributed layout adds up over the real communicator.
#include <gtest/gtest.h>
#include <mpi.h>

#include "common/error.hpp"
#include "mesh/distribution.hpp"
#include "mesh_test_util.hpp"

namespace hs::test {
namespace {

MeshConfig sphere_config() {
  MeshConfig cfg;
  cfg.file = source_mesh("lame_sphere.geo");
  cfg.parameters = {{"a", 1.0}, {"b", 2.0}, {"h", 0.5}};
  cfg.order = 2;
  return cfg;
}

TEST(Replicated, EveryRankGetsTheRootsMesh) {
  const MeshConfig cfg = sphere_config();
  const Mesh copy = load_mesh_replicated(cfg, MPI_COMM_WORLD);
  const Mesh own = load_mesh(cfg);  // gmsh is deterministic: the same mesh everywhere
  EXPECT_EQ(copy.order, own.order);
  EXPECT_EQ(copy.x, own.x);
  EXPECT_EQ(copy.tets, own.tets);
  EXPECT_EQ(copy.tet_volume, own.tet_volume);
  EXPECT_EQ(copy.volume_names, own.volume_names);
  EXPECT_EQ(copy.surfaces, own.surfaces);
  EXPECT_EQ(copy.surface_tets, own.surface_tets);
  EXPECT_EQ(copy.node_groups, own.node_groups);
  EXPECT_EQ(copy.surfaces.size(), 5u);
}

TEST(Replicated, RootCanBeAnyRank) {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const Mesh from_last = load_mesh_replicated(sphere_config(), MPI_COMM_WORLD, size - 1);
  const Mesh from_first = load_mesh_replicated(sphere_config(), MPI_COMM_WORLD, 0);
  EXPECT_EQ(from_last.x, from_first.x);
  EXPECT_EQ(from_last.node_groups, from_first.node_groups);
}

TEST(Replicated, MissingFileFailsOnEveryRank) {
  MeshConfig cfg;
  cfg.file = "/nonexistent/cavity.msh";
  try {
    load_mesh_replicated(cfg, MPI_COMM_WORLD);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/cavity.msh"), std::string::npos);
  }
}

TEST(Replicated, OwnedRangesFormThePetscLayout) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const Mesh mesh = load_mesh_replicated(sphere_config(), MPI_COMM_WORLD);
  std::vector<int> part(mesh.num_tets());
  for (int64_t t = 0; t < mesh.num_tets(); ++t)
    part[t] = static_cast<int>(t * size / mesh.num_tets());
  const Distribution d = distribute(mesh, part, rank, size);
  // The first owned id of each rank is the sum of the owned counts of the ranks before it.
  int64_t owned = d.num_owned(), before = 0, total = 0;
  MPI_Exscan(&owned, &before, 1, MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD);
  if (rank == 0) before = 0;
  MPI_Allreduce(&owned, &total, 1, MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_EQ(d.owned_offsets[rank], before);
  EXPECT_EQ(total, mesh.num_nodes());
  // Every tetrahedron is assembled by exactly one rank.
  int64_t tets = static_cast<int64_t>(d.local_tets.size()), all_tets = 0;
  MPI_Allreduce(&tets, &all_tets, 1, MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_EQ(all_tets, mesh.num_tets());
}

}  // namespace
}  // namespace hs::test
