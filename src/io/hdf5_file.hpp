// A thin RAII layer over the HDF5 C API for the few things the writer needs: groups,
// 1D/2D datasets of double, int64 and int32, and double attributes. Opened with a
// communicator, every call is collective (MPI-IO): each rank writes its own rows of a dataset
// in one collective write, and nothing is gathered anywhere. Opened without one, it is serial.
// Every failure throws std::runtime_error naming the file and the object.
#pragma once

#include <hdf5.h>
#include <mpi.h>

#include <cstdint>
#include <string>
#include <vector>

namespace hs {

// Closes an HDF5 handle (of the kind `close` closes) at scope exit.
struct Hdf5Handle {
  hid_t id;
  herr_t (*close)(hid_t);
  ~Hdf5Handle() {
    if (id >= 0) close(id);
  }
};

class Hdf5File {
 public:
  // Create truncates an existing file; CreateLargeAttributes too, in HDF5's 1.8 format, whose
  // attributes may exceed the 64 KB of the original one (a checkpoint's state).
  enum class Mode { Create, Append, CreateLargeAttributes };
  Hdf5File(const std::string& path, Mode mode, MPI_Comm comm = MPI_COMM_NULL);
  ~Hdf5File();
  Hdf5File(const Hdf5File&) = delete;
  Hdf5File& operator=(const Hdf5File&) = delete;

  void create_group(const std::string& name);
  // rows x cols (cols = 0: a 1D dataset of `rows` entries), row-major data.
  void write(const std::string& name, const std::vector<double>& data, size_t rows, size_t cols);
  void write(const std::string& name, const std::vector<int64_t>& data, size_t rows, size_t cols);
  void write(const std::string& name, const std::vector<int>& data, size_t rows, size_t cols);
  // This rank's rows [first, first + data.size() / max(cols, 1)) of a dataset of `rows` rows.
  void write_rows(const std::string& name, const std::vector<double>& data, size_t rows,
                  size_t cols, size_t first);
  void write_rows(const std::string& name, const std::vector<int64_t>& data, size_t rows,
                  size_t cols, size_t first);
  void write_rows(const std::string& name, const std::vector<int>& data, size_t rows, size_t cols,
                  size_t first);
  void set_attribute(const std::string& object, const std::string& name, double value);
  void set_attribute(const std::string& object, const std::string& name, int value);
  void set_attribute(const std::string& object, const std::string& name, const std::string& value);
  void close();  // flushes; the destructor closes too (without throwing)

 private:
  void write_raw(const std::string& name, hid_t file_type, hid_t memory_type, const void* data,
                 size_t count, size_t rows, size_t cols, size_t first);
  void write_attribute(const std::string& object, const std::string& name, hid_t type,
                       const void* value);
  [[noreturn]] void fail(const std::string& what) const;

  std::string path_;
  hid_t file_ = -1;
  bool parallel_ = false;
};

}  // namespace hs
