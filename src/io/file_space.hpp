// Room on the disk for an HDF5 write, taken before HDF5 writes anything. HDF5 1.10 cannot
// recover from a write that fails for lack of space: the file it then fails to close stays
// registered, half torn down, and the library crashes when it shuts down (in MPI_Finalize:
// SIGSEGV, or "infinite loop closing library"; h5py/h5py#914). So the bytes a write session
// may add are allocated first (fallocate(2), FALLOC_FL_KEEP_SIZE: blocks past the end of the
// file, which later writes fill without allocating), and a full disk or an exhausted quota
// is found there, before HDF5 opens the file. What is left unused is given back after the
// file is closed (release_unused_space).
#pragma once

#include <cstdint>
#include <string>

namespace hs {

// Allocates `bytes` past the end of the file at `path` (created if missing and `create`),
// keeping its size. Returns "" when done, or when the file system cannot allocate ahead (then
// nothing is reserved and a full disk is found by the write itself); otherwise what failed
// and the system's reason: "no room for 62 KB more: No space left on device" (or "Disk quota
// exceeded", "File too large"), "cannot open the file: Permission denied".
std::string reserve_space(const std::string& path, int64_t bytes, bool create);

// Gives back the blocks allocated past the end of the file (best effort).
void release_unused_space(const std::string& path);

// The system's reason for errno: strerror(errno).
std::string system_reason();

}  // namespace hs
