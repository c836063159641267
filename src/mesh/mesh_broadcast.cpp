// load_mesh_replicated: the root rank loads, every other rank receives a full copy.
#include <algorithm>
#include <climits>
#include <iostream>
#include <stdexcept>

#include "common/error.hpp"
#include "mesh/gmsh_io.hpp"
#include "mesh/mesh_checks.hpp"

namespace hs {
namespace {

template <typename T>
MPI_Datatype mpi_type();
template <>
MPI_Datatype mpi_type<double>() {
  return MPI_DOUBLE;
}
template <>
MPI_Datatype mpi_type<int64_t>() {
  return MPI_INT64_T;
}
template <>
MPI_Datatype mpi_type<int>() {
  return MPI_INT;
}
template <>
MPI_Datatype mpi_type<char>() {
  return MPI_CHAR;
}

class Broadcaster {
 public:
  Broadcaster(MPI_Comm comm, int root) : comm_(comm), root_(root) {}

  void scalar(int64_t& value) { MPI_Bcast(&value, 1, MPI_INT64_T, root_, comm_); }

  // Sizes first, then the data in chunks that fit MPI's int counts.
  template <typename T>
  void vector(std::vector<T>& v) {
    int64_t n = static_cast<int64_t>(v.size());
    scalar(n);
    v.resize(n);
    constexpr int64_t kChunk = INT_MAX / 2;
    for (int64_t at = 0; at < n; at += kChunk) {
      const int count = static_cast<int>(std::min(kChunk, n - at));
      MPI_Bcast(v.data() + at, count, mpi_type<T>(), root_, comm_);
    }
  }

  void string(std::string& s) {
    std::vector<char> chars(s.begin(), s.end());
    vector(chars);
    s.assign(chars.begin(), chars.end());
  }

  void strings(std::vector<std::string>& list) {
    int64_t n = static_cast<int64_t>(list.size());
    scalar(n);
    list.resize(n);
    for (auto& s : list) string(s);
  }

  void map(std::map<std::string, std::vector<int64_t>>& m) {
    std::vector<std::string> keys;
    for (const auto& entry : m) keys.push_back(entry.first);
    strings(keys);
    for (const auto& key : keys) vector(m[key]);
  }

 private:
  MPI_Comm comm_;
  int root_;
};

}  // namespace

Mesh load_mesh_replicated(const MeshConfig& cfg, MPI_Comm comm, int root) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  Broadcaster bcast(comm, root);
  // The root's outcome goes first, so that a bad mesh stops every rank with its message.
  enum : int64_t { kLoaded = 0, kInputError = 1, kOtherError = 2 };
  int64_t status = kLoaded;
  std::string message;
  Mesh mesh;
  if (rank == root) {
    try {
      mesh = load_mesh(cfg);
      const std::string warning = units_warning(mesh, cfg.file);
      if (!warning.empty()) std::cerr << "warning: " << warning << std::endl;
    } catch (const InputError& e) {
      status = kInputError;
      message = e.what();
    } catch (const std::exception& e) {
      status = kOtherError;
      message = e.what();
    }
  }
  bcast.scalar(status);
  if (status != kLoaded) {
    bcast.string(message);
    if (status == kInputError) throw InputError(message);
    throw std::runtime_error(message);
  }
  int64_t order = mesh.order;
  bcast.scalar(order);
  mesh.order = static_cast<int>(order);
  bcast.vector(mesh.x);
  bcast.vector(mesh.tets);
  bcast.vector(mesh.tet_volume);
  bcast.strings(mesh.volume_names);
  bcast.map(mesh.surfaces);
  bcast.map(mesh.surface_tets);
  bcast.map(mesh.node_groups);
  return mesh;
}

}  // namespace hs
