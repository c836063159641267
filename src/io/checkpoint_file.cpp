#include "io/checkpoint_file.hpp"

#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "common/error.hpp"
#include "common/exchange.hpp"
#include "io/file_space.hpp"
#include "io/hdf5_file.hpp"

namespace hs {
namespace {

const char* kCheckpointFormat = "hydrosoft checkpoint";
constexpr int kVersion = 1;

}  // namespace

void write_checkpoint(const std::string& path, MPI_Comm comm, const nlohmann::json& state,
                      const CheckpointRows& rows, const NamedValues& fields,
                      const NamedValues& series, const NamedValues& element_fields) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  const std::string tmp = path + ".tmp";
  // Rank 0's text on every rank: HDF5 writes an attribute collectively, and one whose length
  // differs between ranks (a timing measured on each) leaves them waiting on each other in
  // the file's close, for ever.
  std::string text = state.dump();
  broadcast_string(text, 0, comm);
  // What the file takes at most, reserved before HDF5 writes (rank 0's count decides).
  int64_t bytes = 8 * rows.nodes * (1 + 3 * static_cast<int64_t>(fields.size())) +
                  static_cast<int64_t>(text.size()) +
                  Hdf5File::metadata_allowance(8 + 2 * static_cast<int64_t>(fields.size()) +
                                               2 * static_cast<int64_t>(series.size()));
  for (const auto& named : series) bytes += 8 * static_cast<int64_t>(named.second.size());
  if (!element_fields.empty())
    bytes += 8 * rows.elements * (1 + static_cast<int64_t>(element_fields.size())) +
             Hdf5File::metadata_allowance(2 + 2 * static_cast<int64_t>(element_fields.size()));
  try {
    {
      // A control run's state holds its results so far: often more than 64 KB.
      Hdf5File h5(tmp, Hdf5File::Mode::CreateLargeAttributes, comm, bytes);
      h5.set_attribute("/", "format", std::string(kCheckpointFormat));
      h5.set_attribute("/", "version", kVersion);
      h5.set_attribute("/", "state", text);
      h5.write_rows("/node_ids", rows.node_ids, rows.nodes, 0, rows.first);
      h5.create_group("/fields");
      for (const auto& [name, values] : fields)
        h5.write_rows("/fields/" + name, values, rows.nodes, 3, rows.first);
      h5.create_group("/series");
      for (const auto& [name, values] : series) {
        int64_t count = static_cast<int64_t>(values.size());
        MPI_Bcast(&count, 1, MPI_INT64_T, 0, comm);
        h5.write_rows("/series/" + name, values, count, 0, 0);
      }
      if (!element_fields.empty()) {
        h5.write_rows("/element_ids", rows.element_ids, rows.elements, 0, rows.first_element);
        h5.create_group("/element_fields");
        for (const auto& [name, values] : element_fields)
          h5.write_rows("/element_fields/" + name, values, rows.elements, 0, rows.first_element);
      }
      h5.close();
    }
    // Every rank has closed its part before the name changes.
    MPI_Barrier(comm);
    std::string error;
    if (rank == 0 && std::rename(tmp.c_str(), path.c_str()) != 0) {
      error = path + ": cannot replace the checkpoint with " + tmp + ": " + system_reason();
      std::remove(tmp.c_str());
    }
    throw_together<SolveError>(error, comm);
  } catch (const SolveError& e) {
    // The previous checkpoint.h5, if any, is whole: a restart can still start from it.
    throw SolveError("checkpoint not written: " + std::string(e.what()));
  }
}

CheckpointFile::CheckpointFile(const std::string& path) : path_(path) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error))
    fail(error ? "cannot be examined: " + error.message() : "no such file");
  quiet_hdf5();  // a damaged file is said in one line, not in HDF5's error stack
  file_.id = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  auto text_attribute = [&](const char* name) {
    if (file_.id < 0 || H5Aexists(file_.id, name) <= 0) return std::string();
    Hdf5Handle a{H5Aopen(file_.id, name, H5P_DEFAULT), H5Aclose};
    Hdf5Handle type{H5Aget_type(a.id), H5Tclose};
    std::string s(H5Tget_size(type.id), '\0');
    if (H5Tget_class(type.id) != H5T_STRING || H5Aread(a.id, type.id, s.data()) < 0)
      return std::string();
    return s;
  };
  const std::string format = text_attribute("format"), text = text_attribute("state");
  if (file_.id < 0) fail("not an HDF5 file");
  if (format != kCheckpointFormat || text.empty()) fail("not a hydrosoft checkpoint");
  try {
    state_ = nlohmann::json::parse(text);
  } catch (const std::exception&) {
    fail("its state attribute is not JSON");
  }
  Hdf5Handle set{H5Dopen2(file_.id, "/node_ids", H5P_DEFAULT), H5Dclose};
  if (set.id < 0) fail("no /node_ids");
  Hdf5Handle space{H5Dget_space(set.id), H5Sclose};
  hsize_t dims[1] = {0};
  if (H5Sget_simple_extent_ndims(space.id) != 1) fail("/node_ids is not a list");
  H5Sget_simple_extent_dims(space.id, dims, nullptr);
  nodes_ = static_cast<int64_t>(dims[0]);
  if (H5Lexists(file_.id, "/element_ids", H5P_DEFAULT) > 0) {
    Hdf5Handle elements{H5Dopen2(file_.id, "/element_ids", H5P_DEFAULT), H5Dclose};
    Hdf5Handle element_space{H5Dget_space(elements.id), H5Sclose};
    if (H5Sget_simple_extent_ndims(element_space.id) != 1) fail("/element_ids is not a list");
    H5Sget_simple_extent_dims(element_space.id, dims, nullptr);
    elements_ = static_cast<int64_t>(dims[0]);
  }
}

void CheckpointFile::fail(const std::string& reason) const {
  throw InputError("--restart: " + path_ + ": " + reason);
}

template <class T>
std::vector<T> CheckpointFile::rows(const std::string& name, hid_t type, int64_t begin, int64_t end,
                                    int cols) const {
  const hsize_t width = cols ? cols : 1;
  std::vector<T> out((end - begin) * width);
  if (H5Lexists(file_.id, name.c_str(), H5P_DEFAULT) <= 0) fail("no " + name);
  Hdf5Handle set{H5Dopen2(file_.id, name.c_str(), H5P_DEFAULT), H5Dclose};
  Hdf5Handle space{H5Dget_space(set.id), H5Sclose};
  hsize_t dims[2] = {0, 0};
  const int ndims = H5Sget_simple_extent_ndims(space.id);
  H5Sget_simple_extent_dims(space.id, dims, nullptr);
  if (ndims != (cols ? 2 : 1) || static_cast<int64_t>(dims[0]) < end || (cols && dims[1] != width))
    fail(name + ": not the expected shape");
  if (end == begin) return out;
  const hsize_t start[2] = {static_cast<hsize_t>(begin), 0};
  const hsize_t count[2] = {static_cast<hsize_t>(end - begin), width};
  H5Sselect_hyperslab(space.id, H5S_SELECT_SET, start, nullptr, count, nullptr);
  Hdf5Handle memory{H5Screate_simple(cols ? 2 : 1, count, nullptr), H5Sclose};
  if (H5Dread(set.id, type, memory.id, space.id, H5P_DEFAULT, out.data()) < 0)
    fail(name + ": cannot be read");
  return out;
}

std::vector<int64_t> CheckpointFile::node_ids(int64_t begin, int64_t end) const {
  return rows<int64_t>("/node_ids", H5T_NATIVE_INT64, begin, end, 0);
}

std::vector<double> CheckpointFile::field(const std::string& name, int64_t begin,
                                          int64_t end) const {
  return rows<double>("/fields/" + name, H5T_NATIVE_DOUBLE, begin, end, 3);
}

bool CheckpointFile::has_element_field(const std::string& name) const {
  return elements_ > 0 && H5Lexists(file_.id, "/element_fields", H5P_DEFAULT) > 0 &&
         H5Lexists(file_.id, ("/element_fields/" + name).c_str(), H5P_DEFAULT) > 0;
}

std::vector<int64_t> CheckpointFile::element_ids(int64_t begin, int64_t end) const {
  return rows<int64_t>("/element_ids", H5T_NATIVE_INT64, begin, end, 0);
}

std::vector<double> CheckpointFile::element_field(const std::string& name, int64_t begin,
                                                  int64_t end) const {
  return rows<double>("/element_fields/" + name, H5T_NATIVE_DOUBLE, begin, end, 0);
}

std::vector<double> CheckpointFile::series(const std::string& name) const {
  const std::string path = "/series/" + name;
  if (H5Lexists(file_.id, path.c_str(), H5P_DEFAULT) <= 0) return {};
  Hdf5Handle set{H5Dopen2(file_.id, path.c_str(), H5P_DEFAULT), H5Dclose};
  Hdf5Handle space{H5Dget_space(set.id), H5Sclose};
  hsize_t dims[1] = {0};
  H5Sget_simple_extent_dims(space.id, dims, nullptr);
  return rows<double>(path, H5T_NATIVE_DOUBLE, 0, static_cast<int64_t>(dims[0]), 0);
}

}  // namespace hs
