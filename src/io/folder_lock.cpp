#include "io/folder_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>

#include "common/error.hpp"
#include "io/file_space.hpp"

namespace hs {
namespace {

// Whether the open file fd is still the file at `path`: a run that releases its lock
// removes the file, so a lock taken on a file that was removed meanwhile locks nothing.
bool still_at_path(int fd, const std::string& path) {
  struct stat open_file, at_path;
  if (fstat(fd, &open_file) != 0 || stat(path.c_str(), &at_path) != 0) return false;
  return open_file.st_dev == at_path.st_dev && open_file.st_ino == at_path.st_ino;
}

// What the holder of the lock wrote into it ("process 123 on host h"), or "" if nothing yet.
std::string holder_of(int fd) {
  char text[256] = {};
  const ssize_t n = pread(fd, text, sizeof text - 1, 0);
  std::string holder = n > 0 ? std::string(text, static_cast<size_t>(n)) : std::string();
  while (!holder.empty() && (holder.back() == '\n' || holder.back() == '\r')) holder.pop_back();
  return holder;
}

void write_holder(int fd) {
  char host[256] = {};
  gethostname(host, sizeof host - 1);
  const std::string text =
      "process " + std::to_string(getpid()) + " on host " + std::string(host) + "\n";
  // Best effort: the text only makes the message of a refused run more helpful.
  if (ftruncate(fd, 0) != 0) return;
  if (pwrite(fd, text.data(), text.size(), 0) < 0) return;
}

}  // namespace

FolderLock::FolderLock(const std::string& folder) : path_(folder + ".lock") {
  const std::string where = "output folder '" + folder + "': ";
  for (;;) {
    // The run writes its process and host into the lock file: never through a link, into a
    // file that the link's maker chose (O_NOFOLLOW), nor into a file with other names.
    fd_ = open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK, 0644);
    if (fd_ < 0 && errno == ELOOP)
      throw InputError(where + "its lock file '" + path_ +
                       "' is a symbolic link; a run writes into its lock file and does not " +
                       "follow links: remove the link");
    if (fd_ < 0)
      throw InputError(where + "cannot create its lock file '" + path_ + "': " + system_reason());
    struct stat st;
    const bool plain = fstat(fd_, &st) == 0 && S_ISREG(st.st_mode);
    if (plain && st.st_nlink == 0) {
      close(fd_);  // removed just now by the run that held it: take the new one
      continue;
    }
    if (!plain || st.st_nlink != 1) {
      close(fd_);
      fd_ = -1;
      throw InputError(where + "its lock file '" + path_ +
                       "' is not a plain file of its own (a folder, a device or a hard link " +
                       "to another file); a run writes into its lock file: remove it");
    }
    if (flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      const int error = errno;
      const std::string holder = holder_of(fd_);
      close(fd_);
      fd_ = -1;
      if (error == EWOULDBLOCK)
        throw InputError(where + "another run is writing it (" +
                         (holder.empty() ? std::string() : holder + ", ") + "lock file '" + path_ +
                         "'); wait for that run to end or choose another output.folder");
      errno = error;
      throw InputError(where + "cannot lock '" + path_ + "': " + system_reason());
    }
    if (still_at_path(fd_, path_)) break;
    close(fd_);  // the file was removed by the run that held it: take the new one
  }
  write_holder(fd_);
}

FolderLock::~FolderLock() {
  if (fd_ < 0) return;
  // Removed while still locked, so that a run waiting on this file sees it is gone.
  unlink(path_.c_str());
  close(fd_);
}

}  // namespace hs
