// A limit on the size of the files this process writes (RLIMIT_FSIZE), for the tests of
// writes that find no room: a write past it fails with EFBIG ("File too large"), as one on a
// full disk fails with ENOSPC, and hydrosoft's reservation of room meets it the same way
// (io/file_space.hpp). SIGXFSZ, which would end the process, is ignored meanwhile. Both are
// restored at scope exit.
#pragma once

#include <signal.h>
#include <sys/resource.h>

namespace hs::testing {

class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    getrlimit(RLIMIT_FSIZE, &saved_);
    handler_ = signal(SIGXFSZ, SIG_IGN);
    rlimit limit = saved_;
    limit.rlim_cur = bytes;
    setrlimit(RLIMIT_FSIZE, &limit);
  }
  ~FileSizeLimit() {
    setrlimit(RLIMIT_FSIZE, &saved_);
    signal(SIGXFSZ, handler_);
  }
  FileSizeLimit(const FileSizeLimit&) = delete;
  FileSizeLimit& operator=(const FileSizeLimit&) = delete;

 private:
  rlimit saved_{};
  sighandler_t handler_ = SIG_DFL;
};

}  // namespace hs::testing
