#include "io/hdf5_file.hpp"

#include <unistd.h>

#include <stdexcept>

#include "common/error.hpp"
#include "common/exchange.hpp"
#include "io/file_space.hpp"

namespace hs {

void quiet_hdf5() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }

std::string hdf5_reason() {
  struct Found {
    std::string system, mpi, innermost;
  } found;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_DOWNWARD,
      [](unsigned, const H5E_error2_t* e, void* data) -> herr_t {
        auto& f = *static_cast<Found*>(data);
        const std::string desc = e->desc ? e->desc : "";
        // The file drivers write "..., errno = 28, error message = 'No space left on device'".
        const std::string key = "error message = '";
        const size_t at = desc.find(key);
        if (at != std::string::npos) {
          const size_t end = desc.find('\'', at + key.size());
          f.system = desc.substr(at + key.size(), end - at - key.size());
        }
        if (e->min_num == H5E_MPIERRSTR) f.mpi = desc;
        if (!desc.empty()) f.innermost = desc;
        return 0;
      },
      &found);
  H5Eclear2(H5E_DEFAULT);
  std::string reason = !found.system.empty() ? found.system
                       : !found.mpi.empty()  ? found.mpi
                                             : found.innermost;
  for (char& c : reason)
    if (c == '\n' || c == '\r') c = ' ';
  return reason;
}

int64_t Hdf5File::metadata_allowance(int64_t objects, int64_t siblings) {
  // Measured: an output step (a group, 5 datasets, 9 attributes) adds 4.3 KB of metadata; a
  // name in the root group's local heap, which doubles when full, about 16 bytes.
  return 16 * 1024 + 1024 * objects + 64 * siblings;
}

Hdf5File::Hdf5File(const std::string& path, Mode mode, MPI_Comm comm, int64_t reserve)
    : path_(path), comm_(comm) {
  quiet_hdf5();  // a failure is said in one message of ours
  if (comm != MPI_COMM_NULL) {
    int size = 1;
    MPI_Comm_size(comm, &size);
    MPI_Comm_rank(comm, &rank_);
    parallel_ = size > 1;
  }
  created_ = mode != Mode::Append;
  try {
    // The space first: a full disk stops the session before HDF5 has anything to write.
    if (reserve > 0) agree(rank_ == 0 ? reserve_space(path, reserve, created_) : "");
    Hdf5Handle access{H5Pcreate(H5P_FILE_ACCESS), H5Pclose};
    if (parallel_) H5Pset_fapl_mpio(access.id, comm, MPI_INFO_NULL);
    if (mode == Mode::CreateLargeAttributes)
      H5Pset_libver_bounds(access.id, H5F_LIBVER_V18, H5F_LIBVER_LATEST);
    file_ = created_ ? H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access.id)
                     : H5Fopen(path.c_str(), H5F_ACC_RDWR, access.id);
    check(file_ >= 0, created_ ? "cannot create the file" : "cannot open the file");
    // Creating truncated the file, which frees what was reserved: again (HDF5 has written
    // nothing yet).
    if (reserve > 0 && created_) agree(rank_ == 0 ? reserve_space(path, reserve, true) : "");
  } catch (...) {
    discard();
    throw;
  }
}

Hdf5File::~Hdf5File() {
  if (file_ < 0) return;
  if (failed_) {
    discard();
    return;
  }
  H5Fclose(file_);
  if (rank_ == 0) release_unused_space(path_);
}

void Hdf5File::discard() {
  // A created file is of no use unfinished: emptied first, so that closing it (HDF5 writes
  // what it holds) finds room, then removed. An appended file keeps what it had.
  if (file_ >= 0) {
    if (created_ && rank_ == 0 && truncate(path_.c_str(), 0) != 0) {
      // Closed as it is.
    }
    H5Fclose(file_);
    file_ = -1;
  }
  if (created_ && rank_ == 0) unlink(path_.c_str());
  if (!created_ && rank_ == 0) release_unused_space(path_);
}

void Hdf5File::close() {
  if (file_ < 0) return;
  const herr_t status = H5Fclose(file_);
  file_ = -1;
  const std::string reason = status < 0 ? hdf5_reason() : std::string();
  if (rank_ == 0) {
    if (status < 0 && created_)
      unlink(path_.c_str());
    else
      release_unused_space(path_);
  }
  agree(status < 0 ? "cannot close the file: " + (reason.empty() ? "failed" : reason) : "");
}

void Hdf5File::check(bool ok, const std::string& what) {
  if (ok) {
    agree("");
    return;
  }
  const std::string reason = hdf5_reason();
  agree(what + ": " + (reason.empty() ? "failed" : reason));
}

void Hdf5File::agree(const std::string& problem) {
  const std::string error = problem.empty() ? std::string() : path_ + ": " + problem;
  try {
    if (parallel_)
      throw_together<SolveError>(error, comm_);
    else if (!error.empty())
      throw SolveError(error);
  } catch (...) {
    failed_ = true;
    throw;
  }
}

void Hdf5File::create_group(const std::string& name) {
  Hdf5Handle group{H5Gcreate2(file_, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                   H5Gclose};
  check(group.id >= 0, "cannot create group " + name);
}

void Hdf5File::write_raw(const std::string& name, hid_t file_type, hid_t memory_type,
                         const void* data, size_t count, size_t rows, size_t cols, size_t first) {
  const size_t width = cols ? cols : 1;
  const size_t mine = count / width;
  if (count != mine * width || first + mine > rows)
    throw std::invalid_argument(path_ + ": " + name + ": " + std::to_string(count) +
                                " values from row " + std::to_string(first) + " for a " +
                                std::to_string(rows) + " x " + std::to_string(cols) + " dataset");
  const hsize_t dims[2] = {rows, cols};
  Hdf5Handle space{H5Screate_simple(cols ? 2 : 1, dims, nullptr), H5Sclose};
  Hdf5Handle set{space.id < 0 ? -1
                              : H5Dcreate2(file_, name.c_str(), file_type, space.id, H5P_DEFAULT,
                                           H5P_DEFAULT, H5P_DEFAULT),
                 H5Dclose};
  check(set.id >= 0, "cannot create dataset " + name);
  if (rows == 0) return;
  // Every rank takes part in a collective write, those without rows by selecting nothing.
  const hsize_t start[2] = {first, 0}, block[2] = {mine, width};
  Hdf5Handle memory{H5Screate_simple(cols ? 2 : 1, block, nullptr), H5Sclose};
  if (mine == 0) {
    H5Sselect_none(space.id);
    H5Sselect_none(memory.id);
  } else {
    H5Sselect_hyperslab(space.id, H5S_SELECT_SET, start, nullptr, block, nullptr);
  }
  Hdf5Handle transfer{H5Pcreate(H5P_DATASET_XFER), H5Pclose};
  if (parallel_) H5Pset_dxpl_mpio(transfer.id, H5FD_MPIO_COLLECTIVE);
  check(H5Dwrite(set.id, memory_type, memory.id, space.id, transfer.id, data) >= 0,
        "cannot write dataset " + name);
}

void Hdf5File::write(const std::string& name, const std::vector<double>& data, size_t rows,
                     size_t cols) {
  write_rows(name, data, rows, cols, 0);
}

void Hdf5File::write(const std::string& name, const std::vector<int64_t>& data, size_t rows,
                     size_t cols) {
  write_rows(name, data, rows, cols, 0);
}

void Hdf5File::write(const std::string& name, const std::vector<int>& data, size_t rows,
                     size_t cols) {
  write_rows(name, data, rows, cols, 0);
}

void Hdf5File::write_rows(const std::string& name, const std::vector<double>& data, size_t rows,
                          size_t cols, size_t first) {
  write_raw(name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, data.data(), data.size(), rows, cols, first);
}

void Hdf5File::write_rows(const std::string& name, const std::vector<int64_t>& data, size_t rows,
                          size_t cols, size_t first) {
  write_raw(name, H5T_STD_I64LE, H5T_NATIVE_INT64, data.data(), data.size(), rows, cols, first);
}

void Hdf5File::write_rows(const std::string& name, const std::vector<int>& data, size_t rows,
                          size_t cols, size_t first) {
  write_raw(name, H5T_STD_I32LE, H5T_NATIVE_INT, data.data(), data.size(), rows, cols, first);
}

void Hdf5File::write_attribute(const std::string& object, const std::string& name, hid_t type,
                               const void* value) {
  Hdf5Handle space{H5Screate(H5S_SCALAR), H5Sclose};
  Hdf5Handle attribute{H5Acreate_by_name(file_, object.c_str(), name.c_str(), type, space.id,
                                         H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                       H5Aclose};
  check(attribute.id >= 0, "cannot create attribute " + object + "/" + name);
  check(H5Awrite(attribute.id, type, value) >= 0, "cannot write attribute " + object + "/" + name);
}

void Hdf5File::set_attribute(const std::string& object, const std::string& name, double value) {
  write_attribute(object, name, H5T_NATIVE_DOUBLE, &value);
}

void Hdf5File::set_attribute(const std::string& object, const std::string& name, int value) {
  write_attribute(object, name, H5T_NATIVE_INT, &value);
}

void Hdf5File::set_attribute(const std::string& object, const std::string& name,
                             const std::string& value) {
  Hdf5Handle type{H5Tcopy(H5T_C_S1), H5Tclose};
  H5Tset_size(type.id, value.size());
  write_attribute(object, name, type.id, value.data());
}

}  // namespace hs
