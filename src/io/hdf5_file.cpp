#include "io/hdf5_file.hpp"

#include <stdexcept>

namespace hs {
namespace {

// Closes an HDF5 handle at scope exit.
struct Handle {
  hid_t id;
  herr_t (*close)(hid_t);
  ~Handle() {
    if (id >= 0) close(id);
  }
};

}  // namespace

Hdf5File::Hdf5File(const std::string& path, Mode mode) : path_(path) {
  file_ = mode == Mode::Create ? H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT)
                               : H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  if (file_ < 0) fail(mode == Mode::Create ? "cannot create the file" : "cannot open the file");
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
  Handle group{H5Gcreate2(file_, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose};
  if (group.id < 0) fail("cannot create group " + name);
}

void Hdf5File::write_raw(const std::string& name, hid_t file_type, hid_t memory_type,
                         const void* data, size_t count, size_t rows, size_t cols) {
  if (count != rows * (cols ? cols : 1))
    throw std::invalid_argument(path_ + ": " + name + ": " + std::to_string(count) +
                                " values for a " + std::to_string(rows) + " x " +
                                std::to_string(cols) + " dataset");
  const hsize_t dims[2] = {rows, cols};
  Handle space{H5Screate_simple(cols ? 2 : 1, dims, nullptr), H5Sclose};
  if (space.id < 0) fail("cannot create the dataspace of " + name);
  Handle set{
      H5Dcreate2(file_, name.c_str(), file_type, space.id, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
      H5Dclose};
  if (set.id < 0) fail("cannot create dataset " + name);
  if (count > 0 && H5Dwrite(set.id, memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
    fail("cannot write dataset " + name);
}

void Hdf5File::write(const std::string& name, const std::vector<double>& data, size_t rows,
                     size_t cols) {
  write_raw(name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, data.data(), data.size(), rows, cols);
}

void Hdf5File::write(const std::string& name, const std::vector<int64_t>& data, size_t rows,
                     size_t cols) {
  write_raw(name, H5T_STD_I64LE, H5T_NATIVE_INT64, data.data(), data.size(), rows, cols);
}

void Hdf5File::write(const std::string& name, const std::vector<int>& data, size_t rows,
                     size_t cols) {
  write_raw(name, H5T_STD_I32LE, H5T_NATIVE_INT, data.data(), data.size(), rows, cols);
}

void Hdf5File::set_attribute(const std::string& object, const std::string& name, double value) {
  Handle space{H5Screate(H5S_SCALAR), H5Sclose};
  Handle attribute{H5Acreate_by_name(file_, object.c_str(), name.c_str(), H5T_IEEE_F64LE, space.id,
                                     H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                   H5Aclose};
  if (attribute.id < 0) fail("cannot create attribute " + object + "/" + name);
  if (H5Awrite(attribute.id, H5T_NATIVE_DOUBLE, &value) < 0)
    fail("cannot write attribute " + object + "/" + name);
}

}  // namespace hs
