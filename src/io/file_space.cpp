#include "io/file_space.hpp"

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace hs {

std::string system_reason() { return std::strerror(errno); }

std::string reserve_space(const std::string& path, int64_t bytes, bool create) {
  const int fd = open(path.c_str(), O_WRONLY | O_CLOEXEC | (create ? O_CREAT : 0), 0644);
  if (fd < 0) return "cannot open the file: " + system_reason();
  struct stat st;
  int status = fstat(fd, &st);
  // Blocks allocated past the end escape the process's file size limit (RLIMIT_FSIZE), which
  // the writes would then meet: checked here the same way.
  struct rlimit limit;
  if (status == 0 && getrlimit(RLIMIT_FSIZE, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY &&
      static_cast<uint64_t>(st.st_size + bytes) > limit.rlim_cur) {
    status = -1;
    errno = EFBIG;
  }
  if (status == 0 && bytes > 0) status = fallocate(fd, FALLOC_FL_KEEP_SIZE, st.st_size, bytes);
  const int error = errno;
  close(fd);
  // A file system that cannot allocate ahead (some network and FUSE file systems).
  if (status != 0 && (error == EOPNOTSUPP || error == ENOSYS)) return {};
  if (status == 0) return {};
  errno = error;
  return "no room for " + std::to_string((bytes + 1023) / 1024) + " KB more: " + system_reason();
}

void release_unused_space(const std::string& path) {
  // Truncating a file to its own size frees the blocks past its end (ext4, xfs, tmpfs).
  struct stat st;
  if (stat(path.c_str(), &st) == 0 && truncate(path.c_str(), st.st_size) != 0) return;
}

}  // namespace hs
