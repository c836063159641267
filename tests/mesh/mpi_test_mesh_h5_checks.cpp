// Untrusted .h5 meshes (docs/reliability.md, "Untrusted meshes and surfaces"): every way an .h5
// is read (in blocks by every rank for a run, whole by load_mesh for --check and `hydrosoft
// mesh`) refuses what a .msh is refused for, naming the file and the element, node or face,
// and refuses counts that the element limit or the file's stored bytes cannot back before
// reading them. Each file is written by rank 0 from a good mesh into the test's folder, altered
// before writing or after it with HDF5 calls. Runs on 1 and 2 ranks: the same message on
// every rank, whichever rank finds the fault.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <mpi.h>

#include <algorithm>
#include <random>

#include "../mpi_test_folder.hpp"
#include "common/error.hpp"
#include "mesh/mesh_h5.hpp"
#include "mesh/slab_checks.hpp"
#include "mesh_test_util.hpp"
#include "solvers/distributed_mesh.hpp"

namespace hs::test {
namespace {
namespace mpi_test_mesh_h5_checks {

int rank() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

Mesh sphere(int order) {
  return load_geo("lame_sphere.geo", {{"a", 1.0}, {"b", 2.0}, {"h", 0.6}}, order);
}

// `m` written by rank 0 as `name` in the test's folder; its path on every rank.
std::string written(const Mesh& m, const std::string& name) {
  const std::string path = (hs_test::test_folder() / name).string();
  if (rank() == 0) write_mesh_h5(m, path);
  MPI_Barrier(MPI_COMM_WORLD);
  return path;
}

// Rank 0 replaces dataset `name` of the file by one of `rows` x `cols` (0: 1D) entries of
// `type`, created with `dcpl` and written from `data` unless it is null.
void replace_dataset(const std::string& path, const std::string& name, hsize_t rows, hsize_t cols,
                     hid_t type, const void* data, hid_t dcpl = H5P_DEFAULT) {
  if (rank() == 0) {  // no early return: every rank meets at the barrier
    const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    EXPECT_GE(H5Ldelete(file, name.c_str(), H5P_DEFAULT), 0);
    const hsize_t dims[2] = {rows, cols};
    const hid_t space = H5Screate_simple(cols ? 2 : 1, dims, nullptr);
    const hid_t set = H5Dcreate2(file, name.c_str(), type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    EXPECT_GE(set, 0) << name;
    if (data && set >= 0) EXPECT_GE(H5Dwrite(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), 0);
    if (set >= 0) H5Dclose(set);
    H5Sclose(space);
    H5Fclose(file);
  }
  MPI_Barrier(MPI_COMM_WORLD);
}

MeshConfig config(const std::string& path, int64_t max_elements = 20'000'000) {
  MeshConfig cfg;
  cfg.file = path;
  cfg.max_elements = max_elements;
  return cfg;
}

// Refused with a message holding every one of `parts`, the same on every rank, both when
// every rank reads its blocks (a run) and when each process reads it whole (load_mesh).
void expect_refused(const std::string& path, const std::vector<std::string>& parts,
                    int64_t max_elements = 20'000'000) {
  expect_input_error([&] { load_distributed_mesh(config(path, max_elements), MPI_COMM_WORLD); },
                     parts);
  expect_input_error([&] { load_mesh(config(path, max_elements)); }, parts);
}

// The first tetrahedron that holds node n.
int64_t first_tet_with(const Mesh& m, int64_t n) {
  const auto it = std::find(m.tets.begin(), m.tets.end(), n);
  return (it - m.tets.begin()) / m.nodes_per_tet();
}

TEST(H5Checks, GoodMeshesPassAndReadBackUnchanged) {
  const std::vector<Mesh> meshes = {sphere(1), sphere(2), load_geo("block.geo", {{"h", 0.3}}, 2),
                                    load_geo("bimaterial_bar.geo", {{"h", 0.1}})};
  for (size_t i = 0; i < meshes.size(); ++i) {
    const Mesh& m = meshes[i];
    const std::string path = written(m, "good" + std::to_string(i) + ".h5");
    const Mesh whole = load_mesh(config(path));
    EXPECT_EQ(whole.x, m.x);
    EXPECT_EQ(whole.tets, m.tets);
    EXPECT_EQ(whole.surfaces, m.surfaces);
    EXPECT_EQ(whole.surface_tets, m.surface_tets);
    const Distribution d = load_distributed_mesh(config(path), MPI_COMM_WORLD);
    EXPECT_EQ(d.num_global_tets, m.num_tets());
  }
}

TEST(H5Checks, ADuplicatedElementIsRefusedNamingBoth) {
  Mesh m = sphere(1);
  const int64_t copy = m.num_tets();
  m.tets.insert(m.tets.end(), m.tets.begin() + 4 * 5, m.tets.begin() + 4 * 6);
  m.tet_volume.push_back(m.tet_volume[5]);
  const std::string path = written(m, "twice.h5");
  expect_refused(path, {path + ": elements 5 and " + std::to_string(copy) +
                        " (rows of /tets) overlap: they share a face and lie on the same side"});
}

TEST(H5Checks, ADuplicatedNodeIsRefusedNamingBoth) {
  Mesh m = sphere(1);
  const int64_t node = m.tets[4 * 10], copy = m.num_nodes();  // a vertex of many tetrahedra
  ASSERT_LT(first_tet_with(m, node), 10);
  m.x.insert(m.x.end(), m.x.begin() + 3 * node, m.x.begin() + 3 * node + 3);
  m.tets[4 * 10] = copy;  // tetrahedron 10 no longer connected to its neighbours there
  const std::string path = written(m, "node_twice.h5");
  expect_refused(path, {path + ": node " + std::to_string(node) + " at (",
                        ") and node " + std::to_string(copy) + " at (", "are at the same place"});
}

TEST(H5Checks, NodesAHairApartAreTheSamePlaceWhereverTheGridFalls) {
  // 1.04e-12 m apart along each axis, 1.8e-12 m in all: within the tolerance, 1e-12 of the
  // extent (2 m), which a grid of the tolerance's size misses where a cell's border falls
  // between them.
  Mesh m = sphere(1);
  const int64_t node = m.tets[4 * 10], copy = m.num_nodes();
  for (int d = 0; d < 3; ++d) m.x.push_back(m.x[3 * node + d] + 1.04e-12);
  m.tets[4 * 10] = copy;
  const std::string path = written(m, "node_near.h5");
  expect_refused(path, {"node " + std::to_string(node) + " at (",
                        ") and node " + std::to_string(copy) + " at (", "are at the same place"});
}

TEST(H5Checks, ANodeInNoElementIsRefusedNamingTheFile) {
  Mesh m = sphere(1);
  const int64_t extra = m.num_nodes();
  m.x.insert(m.x.end(), {0.5, 0.5, 0.5});
  const std::string path = written(m, "unused.h5");
  expect_refused(path, {path + ": node " + std::to_string(extra) +
                        " at (0.5, 0.5, 0.5) belongs to no "
                        "element"});
}

TEST(H5Checks, InvertedAndDegenerateElementsAreRefusedNamingTheFile) {
  Mesh m = sphere(1);
  std::swap(m.tets[4 * 7 + 1], m.tets[4 * 7 + 2]);
  const std::string inverted = written(m, "inverted.h5");
  expect_refused(inverted, {inverted + ": element 7 (vertices (", "is inverted"});
  m = sphere(1);
  m.tets[4 * 9 + 3] = m.tets[4 * 9];
  const std::string flat = written(m, "flat.h5");
  expect_refused(flat, {flat + ": element 9 (vertices (", "is degenerate (zero volume)"});
}

TEST(H5Checks, ACurvedElementTurnedInsideOutIsRefused) {
  Mesh m = sphere(2);
  // Edge node (0, 1) of tetrahedron 3 pulled through the opposite face.
  const int64_t* t = &m.tets[10 * 3];
  for (int d = 0; d < 3; ++d)
    m.x[3 * t[4] + d] = 2 * m.x[3 * t[3] + d] - 0.5 * (m.x[3 * t[0] + d] + m.x[3 * t[1] + d]);
  const std::string path = written(m, "curved.h5");
  expect_refused(path,
                 {path + ": element " + std::to_string(first_tet_with(m, t[4])) + " (vertices (",
                  "is inverted or curved too strongly"});
}

TEST(H5Checks, AFlippedSurfaceFaceIsRefused) {
  for (int order : {1, 2}) {
    Mesh m = sphere(order);
    const int npf = m.nodes_per_face();
    int64_t* f = &m.surfaces.at("inner")[npf * 3];
    std::swap(f[1], f[2]);
    if (order == 2) std::swap(f[3], f[5]);  // (0, 2, 1): edges (0, 2), (2, 1), (1, 0)
    const std::string path = written(m, "flipped" + std::to_string(order) + ".h5");
    expect_refused(path, {path +
                          ": /surfaces/inner/faces: row 3 is listed inwards: its normal "
                          "points into element " +
                          std::to_string(m.surface_tets.at("inner")[3])});
  }
}

TEST(H5Checks, AFaceOfOtherNodesIsRefused) {
  Mesh m = sphere(1);
  int64_t* f = &m.surfaces.at("outer")[3 * 2];
  std::mt19937 random(29);
  std::uniform_int_distribution<int64_t> node(0, m.num_nodes() - 1);
  for (int k = 0; k < 3; ++k) f[k] = node(random);
  const std::string path = written(m, "foreign.h5");
  expect_refused(
      path, {path + ": /surfaces/outer/faces: row 2 (nodes " + std::to_string(f[0]) + " " +
             std::to_string(f[1]) + " " + std::to_string(f[2]) + ") is not a face of element " +
             std::to_string(m.surface_tets.at("outer")[2])});
  m = sphere(2);
  std::swap(m.surfaces.at("outer")[6 * 2 + 3], m.surfaces.at("outer")[6 * 2 + 4]);
  const std::string p2 = written(m, "edges.h5");
  expect_refused(p2, {p2 + ": /surfaces/outer/faces: row 2 has edge nodes"});
}

TEST(H5Checks, CountsAreCheckedBeforeAnythingIsRead) {
  const Mesh m = sphere(1);
  // A file of some 100 kB claiming 2^31 tetrahedra (never written: no storage).
  std::string path = written(m, "claims.h5");
  replace_dataset(path, "/tets", hsize_t{1} << 31, 4, H5T_STD_I64LE, nullptr);
  replace_dataset(path, "/tet_volume", hsize_t{1} << 31, 0, H5T_STD_I32LE, nullptr);
  expect_refused(path, {path + ": mesh.max_elements: /tets holds 2147483648 tetrahedra, above "
                               "the limit of 20000000 tetrahedra"});
  // Within the limit, but not stored.
  expect_refused(path,
                 {path + ": /tets: claims 2147483648 x 4 entries (68719476736 bytes) but stores 0 "
                         "bytes: hydrosoft writes its datasets whole and uncompressed"},
                 int64_t{1} << 32);
  // More nodes than the tetrahedra can hold.
  path = written(m, "nodes.h5");
  replace_dataset(path, "/nodes", 4 * m.num_tets() + 1, 3, H5T_IEEE_F64LE, nullptr);
  expect_refused(path, {path + ": /nodes: claims " + std::to_string(4 * m.num_tets() + 1) +
                        " rows, more than the 4 nodes of each of the " +
                        std::to_string(m.num_tets()) + " tetrahedra"});
}

TEST(H5Checks, CompressedOrFloatingPointElementsAreRefused) {
  const Mesh m = sphere(1);
  const std::string path = written(m, "gzip.h5");
  const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
  const hsize_t chunk[2] = {static_cast<hsize_t>(m.num_tets() / 3), 4};
  H5Pset_chunk(dcpl, 2, chunk);
  H5Pset_deflate(dcpl, 6);
  replace_dataset(path, "/tets", m.num_tets(), 4, H5T_NATIVE_INT64, m.tets.data(), dcpl);
  H5Pclose(dcpl);
  expect_refused(path,
                 {path + ": /tets: claims " + std::to_string(m.num_tets()) + " x 4 entries (" +
                      std::to_string(32 * m.num_tets()) + " bytes) but stores ",
                  "hydrosoft writes its datasets whole and uncompressed"});
  const std::string floats = written(m, "floats.h5");
  const std::vector<double> tets(m.tets.begin(), m.tets.end());
  replace_dataset(floats, "/tets", m.num_tets(), 4, H5T_NATIVE_DOUBLE, tets.data());
  expect_refused(floats, {floats + ": /tets must hold integers"});
}

TEST(H5Checks, TheCheckTakesTheSlabsOfAnyMesh) {
  // check_mesh_slab on blocks cut from a mesh in memory: nothing but the blocks needed.
  Mesh m = sphere(2);
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  MeshSlab slab = slab_of(m, rank(), size);
  check_mesh_slab(slab, MPI_COMM_WORLD);
  m.tets.insert(m.tets.end(), m.tets.begin(), m.tets.begin() + 10);
  m.tet_volume.push_back(0);
  slab = slab_of(m, rank(), size);
  expect_input_error([&] { check_mesh_slab(slab, MPI_COMM_WORLD); },
                     {"mesh: elements 0 and " + std::to_string(m.num_tets() - 1)});
}

}  // namespace mpi_test_mesh_h5_checks
}  // namespace
}  // namespace hs::test
