// slab_of cuts a whole mesh in blocks; scatter_mesh sends each rank its blocks as one message.
#include "mesh/mesh_slab.hpp"

#include <climits>
#include <cstring>
#include <stdexcept>

#include "common/exchange.hpp"

namespace hs {
namespace {

// Flat byte form of a slab, for one MPI message.
class Packer {
 public:
  template <class T>
  void value(const T& v) {
    const char* p = reinterpret_cast<const char*>(&v);
    bytes.insert(bytes.end(), p, p + sizeof(T));
  }
  template <class T>
  void vector(const std::vector<T>& v) {
    value(static_cast<int64_t>(v.size()));
    const char* p = reinterpret_cast<const char*>(v.data());
    bytes.insert(bytes.end(), p, p + v.size() * sizeof(T));
  }
  void string(const std::string& s) { vector(std::vector<char>(s.begin(), s.end())); }
  std::vector<char> bytes;
};

class Unpacker {
 public:
  explicit Unpacker(const std::vector<char>& bytes) : bytes_(bytes) {}
  template <class T>
  void value(T& v) {
    std::memcpy(&v, take(sizeof(T)), sizeof(T));
  }
  template <class T>
  void vector(std::vector<T>& v) {
    int64_t n = 0;
    value(n);
    v.resize(n);
    if (n) std::memcpy(v.data(), take(n * sizeof(T)), n * sizeof(T));
  }
  void string(std::string& s) {
    std::vector<char> c;
    vector(c);
    s.assign(c.begin(), c.end());
  }

 private:
  const char* take(size_t n) {
    if (at_ + n > bytes_.size()) throw std::logic_error("scatter_mesh: short message");
    const char* p = bytes_.data() + at_;
    at_ += n;
    return p;
  }
  const std::vector<char>& bytes_;
  size_t at_ = 0;
};

std::vector<char> pack(const MeshSlab& s) {
  Packer p;
  p.value(s.order);
  p.value(s.num_nodes);
  p.value(s.num_tets);
  p.value(s.node_begin);
  p.value(s.tet_begin);
  p.vector(s.x);
  p.vector(s.tets);
  p.vector(s.tet_volume);
  p.value(static_cast<int64_t>(s.groups.volumes.size()));
  for (const auto& v : s.groups.volumes) p.string(v);
  p.value(static_cast<int64_t>(s.groups.surface_faces.size()));
  for (const auto& [name, n] : s.groups.surface_faces) {
    p.string(name);
    p.value(n);
  }
  p.value(static_cast<int64_t>(s.groups.group_nodes.size()));
  for (const auto& [name, n] : s.groups.group_nodes) {
    p.string(name);
    p.value(n);
  }
  p.value(static_cast<int64_t>(s.surfaces.size()));
  for (const auto& [name, f] : s.surfaces) {
    p.string(name);
    p.value(f.begin);
    p.vector(f.nodes);
    p.vector(f.tets);
  }
  p.value(static_cast<int64_t>(s.node_groups.size()));
  for (const auto& [name, nodes] : s.node_groups) {
    p.string(name);
    p.vector(nodes);
  }
  return std::move(p.bytes);
}

MeshSlab unpack(const std::vector<char>& bytes) {
  Unpacker u(bytes);
  MeshSlab s;
  u.value(s.order);
  u.value(s.num_nodes);
  u.value(s.num_tets);
  u.value(s.node_begin);
  u.value(s.tet_begin);
  u.vector(s.x);
  u.vector(s.tets);
  u.vector(s.tet_volume);
  int64_t n = 0;
  u.value(n);
  s.groups.volumes.resize(n);
  for (auto& v : s.groups.volumes) u.string(v);
  u.value(n);
  for (int64_t i = 0; i < n; ++i) {
    std::string name;
    u.string(name);
    u.value(s.groups.surface_faces[name]);
  }
  u.value(n);
  for (int64_t i = 0; i < n; ++i) {
    std::string name;
    u.string(name);
    u.value(s.groups.group_nodes[name]);
  }
  u.value(n);
  for (int64_t i = 0; i < n; ++i) {
    std::string name;
    u.string(name);
    MeshSlab::Faces& f = s.surfaces[name];
    u.value(f.begin);
    u.vector(f.nodes);
    u.vector(f.tets);
  }
  u.value(n);
  for (int64_t i = 0; i < n; ++i) {
    std::string name;
    u.string(name);
    u.vector(s.node_groups[name]);
  }
  return s;
}

}  // namespace

MeshSlab slab_of(const Mesh& mesh, int rank, int size) {
  MeshSlab s;
  s.order = mesh.order;
  s.num_nodes = mesh.num_nodes();
  s.num_tets = mesh.num_tets();
  s.groups = groups_of(mesh);
  const int npe = mesh.nodes_per_tet(), npf = mesh.nodes_per_face();
  s.node_begin = block_begin(s.num_nodes, rank, size);
  const int64_t node_end = block_begin(s.num_nodes, rank + 1, size);
  s.x.assign(mesh.x.begin() + 3 * s.node_begin, mesh.x.begin() + 3 * node_end);
  s.tet_begin = block_begin(s.num_tets, rank, size);
  const int64_t tet_end = block_begin(s.num_tets, rank + 1, size);
  s.tets.assign(mesh.tets.begin() + npe * s.tet_begin, mesh.tets.begin() + npe * tet_end);
  s.tet_volume.assign(mesh.tet_volume.begin() + s.tet_begin, mesh.tet_volume.begin() + tet_end);
  for (const auto& [name, faces] : mesh.surfaces) {
    const int64_t n = static_cast<int64_t>(faces.size()) / npf;
    const int64_t b = block_begin(n, rank, size), e = block_begin(n, rank + 1, size);
    MeshSlab::Faces& f = s.surfaces[name];
    f.begin = b;
    f.nodes.assign(faces.begin() + npf * b, faces.begin() + npf * e);
    const auto& tets = mesh.surface_tets.at(name);
    f.tets.assign(tets.begin() + b, tets.begin() + e);
  }
  for (const auto& [name, nodes] : mesh.node_groups) {
    const int64_t n = static_cast<int64_t>(nodes.size());
    s.node_groups[name].assign(nodes.begin() + block_begin(n, rank, size),
                               nodes.begin() + block_begin(n, rank + 1, size));
  }
  return s;
}

Mesh whole_mesh(const MeshSlab& s) {
  if (s.slab_nodes() != s.num_nodes || s.slab_tets() != s.num_tets)
    throw std::logic_error("whole_mesh: the slab holds a part of the mesh only");
  Mesh m;
  m.order = s.order;
  m.x = s.x;
  m.tets = s.tets;
  m.tet_volume = s.tet_volume;
  m.volume_names = s.groups.volumes;
  for (const auto& [name, f] : s.surfaces) {
    m.surfaces[name] = f.nodes;
    m.surface_tets[name] = f.tets;
  }
  m.node_groups = s.node_groups;
  return m;
}

MeshSlab scatter_mesh(const Mesh* mesh, int root, MPI_Comm comm) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  if (rank == root) {
    for (int r = 0; r < size; ++r) {
      if (r == root) continue;
      const std::vector<char> bytes = pack(slab_of(*mesh, r, size));
      if (bytes.size() > static_cast<size_t>(INT_MAX))
        throw std::runtime_error(
            "the mesh is too large to send from one rank: write it once with `hydrosoft mesh "
            "DECK` and run on the .h5 mesh, which every rank reads in parallel");
      const int n = static_cast<int>(bytes.size());
      MPI_Send(&n, 1, MPI_INT, r, 0, comm);
      MPI_Send(bytes.data(), n, MPI_BYTE, r, 1, comm);
    }
    return slab_of(*mesh, root, size);
  }
  int n = 0;
  MPI_Recv(&n, 1, MPI_INT, root, 0, comm, MPI_STATUS_IGNORE);
  std::vector<char> bytes(n);
  MPI_Recv(bytes.data(), n, MPI_BYTE, root, 1, comm, MPI_STATUS_IGNORE);
  return unpack(bytes);
}

}  // namespace hs
