// The parallel mesh path against its simple reference: on every rank, distribute_slabs (blocks
// read per rank, tetrahedra moved to their parts, owners agreed at the nodes' blocks) gives
// exactly what distribute() computes from the whole mesh for the same partition; no rank
// holds more than its part plus one layer of ghost nodes; dual_graph finds exactly the face
// neighbours; the .h5 mesh file read in blocks equals the mesh it was written from. Runs on
// 1 to 4 ranks.
#include <gtest/gtest.h>
#include <mpi.h>
#include <petscsys.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>

#include "../mpi_test_folder.hpp"
#include "common/error.hpp"
#include "common/exchange.hpp"
#include "mesh/distribution.hpp"
#include "mesh/mesh_distribute.hpp"
#include "mesh/mesh_h5.hpp"
#include "mesh_test_util.hpp"
#include "solvers/distributed_mesh.hpp"

namespace hs::test {
namespace {

struct Ranks {
  int rank = 0, size = 1;
  Ranks() {
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
  }
};

Mesh sphere(int order) {
  MeshConfig cfg;
  cfg.file = source_mesh("lame_sphere.geo");
  cfg.parameters = {{"a", 1.0}, {"b", 2.0}, {"h", 0.6}};
  cfg.order = order;
  return load_mesh(cfg);  // gmsh is deterministic: the same mesh on every rank
}

// Two partitions unlike any partitioner's: slices along x (compact parts) and round robin
// (every tetrahedron's neighbours elsewhere: the most ghosts and messages).
std::vector<int> slices(const Mesh& m, int size) {
  std::vector<int> part(m.num_tets());
  const int npe = m.nodes_per_tet();
  for (int64_t t = 0; t < m.num_tets(); ++t) {
    double x = 0;
    for (int k = 0; k < 4; ++k) x += m.x[3 * m.tets[npe * t + k]] / 4;
    part[t] = std::min(size - 1, static_cast<int>((x + 2.0) / 4.0 * size));
  }
  return part;
}

std::vector<int> round_robin(const Mesh& m, int size) {
  std::vector<int> part(m.num_tets());
  for (int64_t t = 0; t < m.num_tets(); ++t) part[t] = static_cast<int>((t * 7) % size);
  return part;
}

void expect_same(const Distribution& a, const Distribution& b) {
  EXPECT_EQ(a.order, b.order);
  EXPECT_EQ(a.num_global_tets, b.num_global_tets);
  EXPECT_EQ(a.owned_offsets, b.owned_offsets);
  EXPECT_EQ(a.local_nodes, b.local_nodes);
  EXPECT_EQ(a.old_of_local, b.old_of_local);
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.local_tets, b.local_tets);
  EXPECT_EQ(a.tet_nodes, b.tet_nodes);
  EXPECT_EQ(a.tet_volume, b.tet_volume);
  EXPECT_EQ(a.groups.volumes, b.groups.volumes);
  EXPECT_EQ(a.groups.surface_faces, b.groups.surface_faces);
  EXPECT_EQ(a.groups.group_nodes, b.groups.group_nodes);
  EXPECT_EQ(a.faces, b.faces);
  EXPECT_EQ(a.face_index, b.face_index);
  EXPECT_EQ(a.node_groups, b.node_groups);
}

void check_against_reference(const Mesh& m, const std::vector<int>& part) {
  const Ranks r;
  const MeshSlab slab = slab_of(m, r.rank, r.size);
  std::vector<int> slab_part(part.begin() + slab.tet_begin,
                             part.begin() + slab.tet_begin + slab.slab_tets());
  const Distribution parallel = distribute_slabs(slab, slab_part, MPI_COMM_WORLD);
  expect_same(parallel, distribute(m, part, r.rank, r.size));
  // One layer of ghosts: every local node is a node of a local tetrahedron, every local
  // tetrahedron is of this part.
  std::vector<char> used(parallel.num_local(), 0);
  for (int32_t n : parallel.tet_nodes) used[n] = 1;
  EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0);
  for (int64_t t : parallel.local_tets) EXPECT_EQ(part[t], r.rank);
}

TEST(DistributeSlabs, EqualsTheReferenceForCompactParts) {
  const Mesh m = sphere(1);
  check_against_reference(m, slices(m, Ranks().size));
}

TEST(DistributeSlabs, EqualsTheReferenceForScatteredPartsOfP2) {
  const Mesh m = sphere(2);
  check_against_reference(m, round_robin(m, Ranks().size));
}

TEST(DistributeSlabs, ScatteredMeshEqualsTheSlabsCutLocally) {
  const Ranks r;
  const Mesh m = sphere(1);
  const MeshSlab sent = scatter_mesh(r.rank == 0 ? &m : nullptr, 0, MPI_COMM_WORLD);
  const MeshSlab cut = slab_of(m, r.rank, r.size);
  EXPECT_EQ(sent.x, cut.x);
  EXPECT_EQ(sent.tets, cut.tets);
  EXPECT_EQ(sent.tet_begin, cut.tet_begin);
  EXPECT_EQ(sent.node_groups, cut.node_groups);
  EXPECT_EQ(sent.groups.surface_faces, cut.groups.surface_faces);
  for (const auto& [name, f] : cut.surfaces) {
    EXPECT_EQ(sent.surfaces.at(name).nodes, f.nodes);
    EXPECT_EQ(sent.surfaces.at(name).tets, f.tets);
    EXPECT_EQ(sent.surfaces.at(name).begin, f.begin);
  }
}

TEST(DualGraph, FindsExactlyTheTetrahedraSharingAFace) {
  const Ranks r;
  const Mesh m = sphere(1);
  const MeshSlab slab = slab_of(m, r.rank, r.size);
  const DualGraph g = dual_graph(slab, MPI_COMM_WORLD);
  // Reference: every face's sorted triple, matched in one map.
  std::map<std::array<int64_t, 3>, std::vector<int64_t>> faces;
  for (int64_t t = 0; t < m.num_tets(); ++t)
    for (int skip = 0; skip < 4; ++skip) {
      std::array<int64_t, 3> f;
      int k = 0;
      for (int a = 0; a < 4; ++a)
        if (a != skip) f[k++] = m.tets[4 * t + a];
      std::sort(f.begin(), f.end());
      faces[f].push_back(t);
    }
  std::map<int64_t, std::set<int64_t>> neighbours;
  for (const auto& [f, tets] : faces)
    if (tets.size() == 2) {
      neighbours[tets[0]].insert(tets[1]);
      neighbours[tets[1]].insert(tets[0]);
    }
  ASSERT_EQ(g.offsets.size(), static_cast<size_t>(slab.slab_tets() + 1));
  for (int64_t i = 0; i < slab.slab_tets(); ++i) {
    const std::set<int64_t> got(g.neighbours.begin() + g.offsets[i],
                                g.neighbours.begin() + g.offsets[i + 1]);
    EXPECT_EQ(got, neighbours[slab.tet_begin + i]) << "tetrahedron " << slab.tet_begin + i;
  }
}

TEST(MeshFile, ReadInBlocksEqualsTheMeshItWasWrittenFrom) {
  const Ranks r;
  const Mesh m = sphere(2);
  const std::string path = (hs_test::test_folder() / "sphere.h5").string();
  if (r.rank == 0) write_mesh_h5(m, path);
  MPI_Barrier(MPI_COMM_WORLD);
  const MeshSlab read = read_mesh_h5(path, 20000000, MPI_COMM_WORLD);
  const MeshSlab cut = slab_of(m, r.rank, r.size);
  EXPECT_EQ(read.order, 2);
  EXPECT_EQ(read.num_nodes, m.num_nodes());
  EXPECT_EQ(read.x, cut.x);
  EXPECT_EQ(read.tets, cut.tets);
  EXPECT_EQ(read.tet_volume, cut.tet_volume);
  EXPECT_EQ(read.groups.volumes, m.volume_names);
  EXPECT_EQ(read.groups.group_nodes, cut.groups.group_nodes);
  EXPECT_EQ(read.node_groups, cut.node_groups);
  for (const auto& [name, f] : cut.surfaces) {
    EXPECT_EQ(read.surfaces.at(name).nodes, f.nodes) << name;
    EXPECT_EQ(read.surfaces.at(name).tets, f.tets) << name;
  }
  if (r.rank == 0) {  // the whole file on one process is the mesh again
    const Mesh whole = whole_mesh(read_mesh_h5(path, 20000000, MPI_COMM_SELF));
    EXPECT_EQ(whole.x, m.x);
    EXPECT_EQ(whole.surfaces, m.surfaces);
    EXPECT_EQ(whole.surface_tets, m.surface_tets);
  }
}

TEST(MeshFile, ANodeNumberOutOfRangeIsNamedOnEveryRank) {
  const Ranks r;
  Mesh m = sphere(1);
  m.tets[4 * (m.num_tets() - 1) + 2] = m.num_nodes() + 5;  // in the last rank's block
  const std::string path = (hs_test::test_folder() / "bad.h5").string();
  if (r.rank == 0) write_mesh_h5(m, path);
  MPI_Barrier(MPI_COMM_WORLD);
  try {
    read_mesh_h5(path, 20000000, MPI_COMM_WORLD);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("/tets: row " + std::to_string(m.num_tets() - 1) + " names node " +
                        std::to_string(m.num_nodes() + 5)),
              std::string::npos)
        << what;
  }
}

TEST(DistributeSlabs, AnInvertedTetrahedronIsNamedWithItsFile) {
  const Ranks r;
  Mesh m = sphere(1);
  std::swap(m.tets[4 * 7 + 1], m.tets[4 * 7 + 2]);
  MeshSlab slab = slab_of(m, r.rank, r.size);
  slab.file = "sphere.h5";
  const std::vector<int> part(slab.slab_tets(), r.rank);
  expect_input_error([&] { distribute_slabs(slab, part, MPI_COMM_WORLD); },
                     {"sphere.h5: tetrahedron 7 is inverted or degenerate"});
}

TEST(PartitionSlab, BalancedPartsThatCutFewFaces) {
  // PTScotch's objective, checked: parts within 5 % of the mean, and far fewer faces cut than
  // a split by tetrahedron index, which cuts nearly every interior face. Repeatable.
  const Ranks r;
  const Mesh m = load_geo("block.geo", {{"h", 0.15}}, 1);
  const MeshSlab slab = slab_of(m, r.rank, r.size);
  const std::vector<int> mine = partition_slab(slab, MPI_COMM_WORLD);
  EXPECT_EQ(mine, partition_slab(slab, MPI_COMM_WORLD));  // one Scotch thread: repeatable
  std::vector<int> counts(r.size), displs(r.size), part(m.num_tets());
  const int n = static_cast<int>(mine.size());
  MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
  for (int k = 1; k < r.size; ++k) displs[k] = displs[k - 1] + counts[k - 1];
  MPI_Allgatherv(mine.data(), n, MPI_INT, part.data(), counts.data(), displs.data(), MPI_INT,
                 MPI_COMM_WORLD);
  std::vector<int64_t> size_of(r.size, 0);
  for (int p : part) ++size_of[p];
  for (int p = 0; p < r.size; ++p)
    EXPECT_LE(size_of[p], 1.05 * m.num_tets() / r.size + 1) << "part " << p;
  const DualGraph whole = dual_graph(slab_of(m, 0, 1), MPI_COMM_SELF);
  int64_t interior = 0, cut = 0;
  for (int64_t t = 0; t < m.num_tets(); ++t)
    for (int64_t k = whole.offsets[t]; k < whole.offsets[t + 1]; ++k) {
      ++interior;
      cut += part[t] != part[whole.neighbours[k]];
    }
  EXPECT_LE(cut, interior / 10);
}

// The partitioner has its own options (prefix hs_partition_), from the deck and the command
// line, as a solver object's: PETSc's "current" partitioner keeps every tetrahedron on its rank.
TEST(PartitionSlab, TakesItsOwnOptionsFromTheDeckAndTheCommandLine) {
  const Ranks r;
  if (r.size < 2) GTEST_SKIP() << "needs 2 ranks";
  const Mesh m = load_geo("block.geo", {{"h", 0.3}}, 1);
  const MeshSlab slab = slab_of(m, r.rank, r.size);
  const std::vector<int> kept(slab.slab_tets(), r.rank);
  ASSERT_NE(partition_slab(slab, MPI_COMM_WORLD), kept);  // PTScotch moves some
  for (const char* name : {"hs_partition_mat_partitioning_type", "mat_partitioning_type"}) {
    SolverConfig solver;
    solver.petsc_options = {{name, "current"}};
    EXPECT_EQ(partition_slab(slab, MPI_COMM_WORLD, solver), kept) << name;
  }
  PetscOptionsSetValue(nullptr, "-hs_partition_mat_partitioning_type", "current");
  EXPECT_EQ(partition_slab(slab, MPI_COMM_WORLD), kept);
  PetscOptionsClearValue(nullptr, "-hs_partition_mat_partitioning_type");
}

TEST(LoadDistributedMesh, AMissingFileFailsOnEveryRankWithTheRootsMessage) {
  MeshConfig cfg;
  cfg.file = "/nonexistent/cavity.msh";
  try {
    load_distributed_mesh(cfg, MPI_COMM_WORLD);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/cavity.msh"), std::string::npos);
  }
}

TEST(PartitionSlab, MorePartsThanTetrahedraIsAnError) {
  const Ranks r;
  if (r.size < 2) GTEST_SKIP() << "needs 2 ranks";
  Mesh m = load_geo("block.geo", {{"h", 2.0}}, 1);
  // Keep one tetrahedron (and its nodes): fewer tetrahedra than ranks.
  m.tets.resize(4);
  m.tet_volume.resize(1);
  EXPECT_THROW(partition_slab(slab_of(m, r.rank, r.size), MPI_COMM_WORLD), InputError);
}

}  // namespace
}  // namespace hs::test
