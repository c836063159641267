#include "io/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <stdexcept>
#include <utility>

#include "io/file_space.hpp"

namespace hs {

StagedFile::StagedFile(std::string path, const std::string& text)
    : path_(std::move(path)), tmp_(path_ + ".tmp") {
  const int fd = open(tmp_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error(tmp_ + ": cannot write the file: " + system_reason());
  std::string error;
  for (size_t done = 0; done < text.size() && error.empty();) {
    const ssize_t n = write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) error = system_reason();
    if (n > 0) done += static_cast<size_t>(n);
  }
  if (close(fd) != 0 && error.empty()) error = system_reason();
  if (error.empty()) return;
  // The unfinished file goes, with the space it took.
  std::remove(tmp_.c_str());
  throw std::runtime_error(path_ + ": cannot write the file: " + error);
}

StagedFile::~StagedFile() {
  if (!committed_) std::remove(tmp_.c_str());
}

void StagedFile::commit() {
  if (std::rename(tmp_.c_str(), path_.c_str()) != 0)
    throw std::runtime_error(path_ + ": cannot replace it with " + tmp_ + ": " + system_reason());
  committed_ = true;
}

void write_file_atomically(const std::string& path, const std::string& text) {
  StagedFile(path, text).commit();
}

}  // namespace hs
