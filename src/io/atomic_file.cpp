#include "io/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <stdexcept>

#include "io/file_space.hpp"

namespace hs {

void write_file_atomically(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  const int fd = open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error(tmp + ": cannot write the file: " + system_reason());
  std::string error;
  for (size_t done = 0; done < text.size() && error.empty();) {
    const ssize_t n = write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) error = system_reason();
    if (n > 0) done += static_cast<size_t>(n);
  }
  if (close(fd) != 0 && error.empty()) error = system_reason();
  if (error.empty() && std::rename(tmp.c_str(), path.c_str()) != 0)
    error = "cannot replace it with " + tmp + ": " + system_reason();
  else if (!error.empty())
    error = "cannot write the file: " + error;
  if (error.empty()) return;
  // The previous file stays whole; the unfinished one goes, with the space it took.
  std::remove(tmp.c_str());
  throw std::runtime_error(path + ": " + error);
}

}  // namespace hs
