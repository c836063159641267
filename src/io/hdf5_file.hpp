// A thin RAII layer over the HDF5 C API for the few things the writer needs: groups,
// 1D/2D datasets of double, int64 and int32, and double attributes. Opened with a
// communicator, every call is collective (MPI-IO): each rank writes its own rows of a dataset
// in one collective write, and nothing is gathered anywhere. Opened without one, it is serial.
//
// Failures: every call's outcome is agreed by all ranks before the next one (write_together's
// rule), so a write that fails on one rank stops every rank at the same point, each throwing
// SolveError with the file's path, what failed and the system's reason taken from HDF5's
// error stack ("No space left on device"). HDF5's own printing of that stack is off. With
// `reserve` the space a session may add is allocated before HDF5 writes (file_space.hpp), so
// that a full disk is found before any HDF5 write can fail. A file opened with a Create mode
// is removed when a call fails (an unfinished file is of no use).
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

// Turns HDF5's automatic printing of its error stack off, for good: hydrosoft says what failed
// in one line of its own. For good, because turning it back on after HDF5 had met a damaged
// file made HDF5 print "infinite loop closing library" when the process ended.
void quiet_hdf5();

// Why the last HDF5 call failed, in a few words: the system's reason when the stack holds one
// ("No space left on device"), else MPI's, else HDF5's innermost message. Clears the stack.
std::string hdf5_reason();

class Hdf5File {
 public:
  // Create truncates an existing file; CreateLargeAttributes too, in HDF5's 1.8 format, whose
  // attributes may exceed the 64 KB of the original one (a checkpoint's state).
  enum class Mode { Create, Append, CreateLargeAttributes };
  // reserve: the bytes this session may add at most (0: nothing reserved). Data sizes plus
  // metadata_allowance() for the objects the session makes.
  Hdf5File(const std::string& path, Mode mode, MPI_Comm comm = MPI_COMM_NULL, int64_t reserve = 0);
  ~Hdf5File();
  Hdf5File(const Hdf5File&) = delete;
  Hdf5File& operator=(const Hdf5File&) = delete;

  // An upper bound of the metadata that `objects` new groups, datasets and attributes add to
  // a file whose root holds `siblings` objects already (HDF5's headers, B-trees, heaps).
  static int64_t metadata_allowance(int64_t objects, int64_t siblings = 0);

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
  // Agreed by every rank: throws SolveError on all of them when `ok` is false on any, with
  // the path, `what` and HDF5's reason.
  void check(bool ok, const std::string& what);
  // The same with this rank's problem ("" if none): "<path>: <problem>" on every rank.
  void agree(const std::string& problem);
  // After a failure: closes the file; a created one is emptied first and removed.
  void discard();

  std::string path_;
  hid_t file_ = -1;
  MPI_Comm comm_ = MPI_COMM_NULL;
  int rank_ = 0;
  bool parallel_ = false, created_ = false, failed_ = false;
};

}  // namespace hs
