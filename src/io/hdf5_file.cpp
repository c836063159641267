#include "io/hdf5_file.hpp"

#include <stdexcept>

namespace hs {
Hdf5File::Hdf5File(const std::string& path, Mode mode, MPI_Comm comm) : path_(path) {
  Hdf5Handle access{H5Pcreate(H5P_FILE_ACCESS), H5Pclose};
  if (comm != MPI_COMM_NULL) {
    int size = 1;
    MPI_Comm_size(comm, &size);
    parallel_ = size > 1;
    if (parallel_) H5Pset_fapl_mpio(access.id, comm, MPI_INFO_NULL);
  }
  const bool create = mode != Mode::Append;
  if (mode == Mode::CreateLargeAttributes)
    H5Pset_libver_bounds(access.id, H5F_LIBVER_V18, H5F_LIBVER_LATEST);
  file_ = create ? H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access.id)
                 : H5Fopen(path.c_str(), H5F_ACC_RDWR, access.id);
  if (file_ < 0) fail(create ? "cannot create the file" : "cannot open the file");
}

Hdf5File::~Hdf5File() {
  if (file_ >= 0) H5Fclose(file_);
}

void Hdf5File::close() {
  if (file_ < 0) return;
  const herr_t status = H5Fclose(file_);
  file_ = -1;
  if (status < 0) fail("cannot close the file");
}

void Hdf5File::fail(const std::string& what) const {
  throw std::runtime_error(path_ + ": HDF5: " + what);
}

void Hdf5File::create_group(const std::string& name) {
  Hdf5Handle group{H5Gcreate2(file_, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                   H5Gclose};
  if (group.id < 0) fail("cannot create group " + name);
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
  if (space.id < 0) fail("cannot create the dataspace of " + name);
  Hdf5Handle set{
      H5Dcreate2(file_, name.c_str(), file_type, space.id, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
      H5Dclose};
  if (set.id < 0) fail("cannot create dataset " + name);
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
  if (H5Dwrite(set.id, memory_type, memory.id, space.id, transfer.id, data) < 0)
    fail("cannot write dataset " + name);
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
  if (attribute.id < 0) fail("cannot create attribute " + object + "/" + name);
  if (H5Awrite(attribute.id, type, value) < 0)
    fail("cannot write attribute " + object + "/" + name);
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
