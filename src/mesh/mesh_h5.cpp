// The mesh file in HDF5: written once by one process, read by all in blocks (mesh_h5.hpp).
// Reads are independent (each rank its hyperslabs): the blocks do not overlap, and a
// collective read would make every rank wait for the slowest.
#include "mesh/mesh_h5.hpp"

#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "common/error.hpp"
#include "common/exchange.hpp"
#include "io/hdf5_file.hpp"
#include "mesh/slab_checks.hpp"

namespace hs {
namespace {

const char* kMeshFormat = "hydrosoft mesh";

// A byte count as people read it: 68719476736 -> "68719476736" (exact below 2^53).
std::string byte_count_text(double bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.0f", bytes);
  return text;
}

void check_name(const std::string& path, const std::string& name) {
  if (name.empty() || name.find('/') != std::string::npos || name == "." || name == "..")
    throw InputError(path + ": the group name '" + name +
                     "' cannot be written to HDF5 (it is empty or holds '/')");
}

// Reading: every failure is recorded as the first error and ends the read on every rank.
class Reader {
 public:
  Reader(const std::string& path, MPI_Comm comm) : path_(path) {
    int size = 1;
    MPI_Comm_size(comm, &size);
    Hdf5Handle fapl{H5Pcreate(H5P_FILE_ACCESS), H5Pclose};
    if (size > 1) H5Pset_fapl_mpio(fapl.id, comm, MPI_INFO_NULL);
    // Closing the file closes whatever of it is still open: an object that a damaged file left
    // open made HDF5 print "infinite loop closing library" at the process's end.
    H5Pset_fclose_degree(fapl.id, H5F_CLOSE_STRONG);
    file_ = H5Fopen(path.c_str(), H5F_ACC_RDONLY, fapl.id);
  }
  ~Reader() {
    if (file_ >= 0) H5Fclose(file_);
  }
  bool open() const { return file_ >= 0; }
  std::string format() const {
    Hdf5Handle a{H5Aopen(file_, "format", H5P_DEFAULT), H5Aclose};
    if (a.id < 0) return {};
    Hdf5Handle type{H5Aget_type(a.id), H5Tclose};
    std::string s(H5Tget_size(type.id), '\0');
    if (H5Tget_class(type.id) != H5T_STRING || H5Aread(a.id, type.id, s.data()) < 0) return {};
    return s;
  }
  int attribute(const std::string& object, const std::string& name, int fallback) const {
    int value = fallback;
    Hdf5Handle a{H5Aopen_by_name(file_, object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT),
                 H5Aclose};
    if (a.id < 0 || H5Aread(a.id, H5T_NATIVE_INT, &value) < 0) return fallback;
    return value;
  }
  // What a dataset claims to hold and what the file stores of it.
  struct Shape {
    int64_t rows = -1;  // -1: missing, or not 1D/2D
    int cols = 0;       // 0 for a 1D dataset
    H5T_class_t type = H5T_NO_CLASS;
    double claimed_bytes = 0;  // rows x cols x the size of an entry in the file
    double stored_bytes = 0;   // H5Dget_storage_size
  };
  Shape shape(const std::string& name) const {
    Shape s;
    if (H5Lexists(file_, name.c_str(), H5P_DEFAULT) <= 0) return s;
    Hdf5Handle set{H5Dopen2(file_, name.c_str(), H5P_DEFAULT), H5Dclose};
    if (set.id < 0) return s;
    Hdf5Handle space{H5Dget_space(set.id), H5Sclose};
    Hdf5Handle type{H5Dget_type(set.id), H5Tclose};
    const int rank = H5Sget_simple_extent_ndims(space.id);
    hsize_t dims[2] = {0, 0};
    if (rank < 1 || rank > 2 || type.id < 0) return s;
    H5Sget_simple_extent_dims(space.id, dims, nullptr);
    // Counts beyond 2^62 cannot be stored anywhere; keep them from overflowing int64_t.
    s.rows = static_cast<int64_t>(std::min<hsize_t>(dims[0], hsize_t{1} << 62));
    s.cols = rank == 2 ? static_cast<int>(std::min<hsize_t>(dims[1], 1 << 30)) : 0;
    s.type = H5Tget_class(type.id);
    s.claimed_bytes = static_cast<double>(dims[0]) * static_cast<double>(rank == 2 ? dims[1] : 1) *
                      static_cast<double>(H5Tget_size(type.id));
    s.stored_bytes = static_cast<double>(H5Dget_storage_size(set.id));
    return s;
  }
  double file_bytes() const {
    hsize_t size = 0;
    return H5Fget_filesize(file_, &size) < 0 ? 0 : static_cast<double>(size);
  }
  // Rows [begin, end) of a dataset with `cols` columns (0: 1D).
  template <class T>
  bool rows(const std::string& name, hid_t type, int64_t begin, int64_t end, int cols,
            std::vector<T>& out) const {
    const size_t width = cols ? cols : 1;
    out.resize((end - begin) * width);
    if (end == begin) return true;
    Hdf5Handle set{H5Dopen2(file_, name.c_str(), H5P_DEFAULT), H5Dclose};
    if (set.id < 0) return false;
    Hdf5Handle space{H5Dget_space(set.id), H5Sclose};
    const hsize_t start[2] = {static_cast<hsize_t>(begin), 0};
    const hsize_t count[2] = {static_cast<hsize_t>(end - begin), width};
    H5Sselect_hyperslab(space.id, H5S_SELECT_SET, start, nullptr, count, nullptr);
    Hdf5Handle memory{H5Screate_simple(cols ? 2 : 1, count, nullptr), H5Sclose};
    return H5Dread(set.id, type, memory.id, space.id, H5P_DEFAULT, out.data()) >= 0;
  }
  std::vector<std::string> children(const std::string& group) const {
    std::vector<std::string> names;
    if (H5Lexists(file_, group.c_str(), H5P_DEFAULT) <= 0) return names;
    H5Literate_by_name(
        file_, group.c_str(), H5_INDEX_NAME, H5_ITER_INC, nullptr,
        [](hid_t, const char* name, const H5L_info_t*, void* list) -> herr_t {
          static_cast<std::vector<std::string>*>(list)->push_back(name);
          return 0;
        },
        &names, H5P_DEFAULT);
    return names;
  }

 private:
  std::string path_;
  hid_t file_ = -1;
};

}  // namespace

void write_mesh_h5(const Mesh& mesh, const std::string& path) {
  for (const auto& v : mesh.volume_names) check_name(path, v);
  for (const auto& [name, faces] : mesh.surfaces) check_name(path, name);
  for (const auto& [name, nodes] : mesh.node_groups) check_name(path, name);
  Hdf5File h5(path, Hdf5File::Mode::Create);
  h5.set_attribute("/", "format", std::string(kMeshFormat));
  h5.set_attribute("/", "version", 1);
  h5.set_attribute("/", "order", mesh.order);
  h5.write("/nodes", mesh.x, mesh.num_nodes(), 3);
  h5.write("/tets", mesh.tets, mesh.num_tets(), mesh.nodes_per_tet());
  h5.write("/tet_volume", mesh.tet_volume, mesh.num_tets(), 0);
  h5.create_group("/volumes");
  for (size_t v = 0; v < mesh.volume_names.size(); ++v) {
    h5.create_group("/volumes/" + mesh.volume_names[v]);
    h5.set_attribute("/volumes/" + mesh.volume_names[v], "index", static_cast<int>(v));
  }
  const int npf = mesh.nodes_per_face();
  h5.create_group("/surfaces");
  for (const auto& [name, faces] : mesh.surfaces) {
    h5.create_group("/surfaces/" + name);
    h5.write("/surfaces/" + name + "/faces", faces, faces.size() / npf, npf);
    const auto& tets = mesh.surface_tets.at(name);
    h5.write("/surfaces/" + name + "/tets", tets, tets.size(), 0);
  }
  h5.create_group("/node_groups");
  for (const auto& [name, nodes] : mesh.node_groups)
    h5.write("/node_groups/" + name, nodes, nodes.size(), 0);
  h5.close();
}

MeshSlab read_mesh_h5(const std::string& path, int64_t max_elements, MPI_Comm comm) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  quiet_hdf5();  // failures become our messages
  Reader h5(path, comm);
  MeshSlab s;
  s.file = path;
  std::string error;
  auto fail = [&](const std::string& what) {
    if (error.empty()) error = path + ": " + what;
  };
  if (!h5.open())
    fail("cannot open it as an HDF5 file");
  else if (h5.format() != kMeshFormat)
    fail("not a hydrosoft mesh (no attribute format = '" + std::string(kMeshFormat) +
         "'; write one with `hydrosoft mesh DECK`)");
  throw_together<InputError>(error, comm);

  s.order = h5.attribute("/", "order", 0);
  if (s.order != 1 && s.order != 2) fail("attribute order must be 1 or 2");
  throw_together<InputError>(error, comm);
  const int npe = s.nodes_per_tet(), npf = s.nodes_per_face();

  // Every count is checked before anything is allocated for it: against the element limit
  // and the counts it bounds, and against what the file stores. hydrosoft writes its datasets
  // whole, contiguous and uncompressed, so a dataset stored in fewer bytes than it claims
  // (compressed, or never written) did not come from it, and all of them fit in the file.
  const double file_bytes = h5.file_bytes();
  double stored_total = 0;
  auto check_stored = [&](const std::string& name, const Reader::Shape& shape, H5T_class_t type) {
    if (shape.type != type)
      fail(name + " must hold " + (type == H5T_FLOAT ? "floating-point numbers" : "integers"));
    else if (shape.stored_bytes < shape.claimed_bytes)
      fail(name + ": claims " + std::to_string(shape.rows) +
           (shape.cols ? " x " + std::to_string(shape.cols) : std::string()) + " entries (" +
           byte_count_text(shape.claimed_bytes) + " bytes) but stores " +
           byte_count_text(shape.stored_bytes) +
           " bytes: hydrosoft writes its datasets whole and uncompressed");
    stored_total += shape.stored_bytes;
  };
  auto within = [&](const std::string& name, int64_t rows, int64_t most, const std::string& why) {
    if (rows <= most) return true;
    fail(name + ": claims " + std::to_string(rows) + " rows, more than " + why);
    return false;
  };
  const Reader::Shape tets = h5.shape("/tets");
  if (tets.rows < 1 || tets.cols != npe)
    fail("/tets must be a T x " + std::to_string(npe) + " dataset with T >= 1");
  else if (tets.rows > max_elements)
    fail("mesh.max_elements: /tets holds " + std::to_string(tets.rows) +
         " tetrahedra, above the limit of " + std::to_string(max_elements) +
         " tetrahedra (raise mesh.max_elements)");
  else
    check_stored("/tets", tets, H5T_INTEGER);
  throw_together<InputError>(error, comm);
  s.num_tets = tets.rows;
  const Reader::Shape nodes = h5.shape("/nodes"), vol = h5.shape("/tet_volume");
  if (nodes.rows < 0 || nodes.cols != 3)
    fail("/nodes must be an N x 3 dataset");
  else if (within("/nodes", nodes.rows, npe * s.num_tets,
                  "the " + std::to_string(npe) + " nodes of each of the " +
                      std::to_string(s.num_tets) + " tetrahedra"))
    check_stored("/nodes", nodes, H5T_FLOAT);
  if (vol.rows != tets.rows || vol.cols != 0)
    fail("/tet_volume must hold one entry per tetrahedron");
  else
    check_stored("/tet_volume", vol, H5T_INTEGER);
  const std::vector<std::string> volumes = h5.children("/volumes");
  s.groups.volumes.assign(volumes.size(), "");
  for (const auto& v : volumes) {
    const int index = h5.attribute("/volumes/" + v, "index", -1);
    if (index < 0 || index >= static_cast<int>(volumes.size()) || !s.groups.volumes[index].empty())
      fail("/volumes/" + v + ": its index is missing, out of range or repeated");
    else
      s.groups.volumes[index] = v;
  }
  const std::vector<std::string> surfaces = h5.children("/surfaces");
  for (const auto& name : surfaces) {
    const std::string at = "/surfaces/" + name;
    const Reader::Shape faces = h5.shape(at + "/faces"), bounds = h5.shape(at + "/tets");
    if (faces.rows < 0 || faces.cols != npf || bounds.rows != faces.rows || bounds.cols != 0) {
      fail(at + ": faces must be F x " + std::to_string(npf) + " and tets F entries");
    } else if (within(at + "/faces", faces.rows, 4 * s.num_tets,
                      "the 4 faces of each of the " + std::to_string(s.num_tets) + " tetrahedra")) {
      check_stored(at + "/faces", faces, H5T_INTEGER);
      check_stored(at + "/tets", bounds, H5T_INTEGER);
    }
    s.groups.surface_faces[name] = faces.rows;
  }
  const std::vector<std::string> node_groups = h5.children("/node_groups");
  for (const auto& name : node_groups) {
    const std::string at = "/node_groups/" + name;
    const Reader::Shape n = h5.shape(at);
    if (n.rows < 0 || n.cols != 0)
      fail(at + " must be a 1D dataset");
    else if (within(at, n.rows, nodes.rows, "the mesh's " + std::to_string(nodes.rows) + " nodes"))
      check_stored(at, n, H5T_INTEGER);
    s.groups.group_nodes[name] = n.rows;
  }
  if (error.empty() && stored_total > file_bytes)
    fail("its datasets claim " + byte_count_text(stored_total) +
         " bytes of storage, more than the " + byte_count_text(file_bytes) + "-byte file holds");
  throw_together<InputError>(error, comm);
  s.num_nodes = nodes.rows;

  s.node_begin = block_begin(s.num_nodes, rank, size);
  s.tet_begin = block_begin(s.num_tets, rank, size);
  if (!h5.rows("/nodes", H5T_NATIVE_DOUBLE, s.node_begin, block_begin(s.num_nodes, rank + 1, size),
               3, s.x))
    fail("cannot read /nodes");
  if (!h5.rows("/tets", H5T_NATIVE_INT64, s.tet_begin, block_begin(s.num_tets, rank + 1, size), npe,
               s.tets))
    fail("cannot read /tets");
  if (!h5.rows("/tet_volume", H5T_NATIVE_INT, s.tet_begin, block_begin(s.num_tets, rank + 1, size),
               0, s.tet_volume))
    fail("cannot read /tet_volume");
  for (size_t i = 0; i < s.x.size(); ++i)
    if (!std::isfinite(s.x[i])) {
      fail("/nodes: node " + std::to_string(s.node_begin + i / 3) +
           " has a coordinate that is not finite");
      break;
    }
  auto node_in_range = [&](const std::string& where, const std::vector<int64_t>& list,
                           int64_t first, int width) {
    for (size_t i = 0; i < list.size(); ++i)
      if (list[i] < 0 || list[i] >= s.num_nodes) {
        fail(where + ": row " + std::to_string(first + static_cast<int64_t>(i) / width) +
             " names node " + std::to_string(list[i]) + ", outside 0.." +
             std::to_string(s.num_nodes - 1));
        return;
      }
  };
  node_in_range("/tets", s.tets, s.tet_begin, npe);
  for (size_t i = 0; i < s.tet_volume.size(); ++i)
    if (s.tet_volume[i] < 0 || s.tet_volume[i] >= static_cast<int>(volumes.size())) {
      fail("/tet_volume: tetrahedron " + std::to_string(s.tet_begin + i) + " names volume " +
           std::to_string(s.tet_volume[i]) + ", which /volumes does not hold");
      break;
    }

  for (const auto& name : surfaces) {
    const std::string at = "/surfaces/" + name;
    const int64_t count = s.groups.surface_faces.at(name);
    MeshSlab::Faces& f = s.surfaces[name];
    f.begin = block_begin(count, rank, size);
    const int64_t end = block_begin(count, rank + 1, size);
    if (!h5.rows(at + "/faces", H5T_NATIVE_INT64, f.begin, end, npf, f.nodes) ||
        !h5.rows(at + "/tets", H5T_NATIVE_INT64, f.begin, end, 0, f.tets))
      fail("cannot read " + at);
    node_in_range(at + "/faces", f.nodes, f.begin, npf);
    for (int64_t t : f.tets)
      if (t < 0 || t >= s.num_tets) {
        fail(at + "/tets: tetrahedron " + std::to_string(t) + " is out of range");
        break;
      }
  }
  for (const auto& name : node_groups) {
    const std::string at = "/node_groups/" + name;
    const int64_t count = s.groups.group_nodes.at(name);
    std::vector<int64_t>& list = s.node_groups[name];
    if (!h5.rows(at, H5T_NATIVE_INT64, block_begin(count, rank, size),
                 block_begin(count, rank + 1, size), 0, list))
      fail("cannot read " + at);
    node_in_range(at, list, block_begin(count, rank, size), 1);
  }
  throw_together<InputError>(error, comm);
  check_mesh_slab(s, comm);
  return s;
}

}  // namespace hs
