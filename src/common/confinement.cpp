// Three layers, each enough against a .geo's shell command on its own, so that a kernel that
// lacks one of them still confines: seccomp stops execve itself; Landlock stops opening any
// file to execute, write, create or remove it; RLIMIT_FSIZE = 0 stops a write from growing
// any regular file (the one layer left on a kernel without seccomp filters and Landlock).
#include "common/confinement.hpp"

#include <linux/landlock.h>
#include <seccomp.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <initializer_list>

namespace hs {
namespace {

// Rights of later Landlock versions than the build machine's header may know.
constexpr uint64_t kRefer = 1ULL << 13;     // ABI 2
constexpr uint64_t kTruncate = 1ULL << 14;  // ABI 3

void limit(int resource, rlim_t value) {
  const struct rlimit r = {value, value};
  setrlimit(resource, &r);
}

bool apply_seccomp() {
  scmp_filter_ctx filter = seccomp_init(SCMP_ACT_ALLOW);
  if (!filter) return false;
  bool ok = true;
  // No program started (a shell command is one), no network, no reaching into another
  // process, no io_uring (whose operations seccomp does not see).
  for (int call : {SCMP_SYS(execve), SCMP_SYS(execveat), SCMP_SYS(socket), SCMP_SYS(ptrace),
                   SCMP_SYS(process_vm_writev), SCMP_SYS(io_uring_setup)})
    ok = ok && seccomp_rule_add(filter, SCMP_ACT_ERRNO(EPERM), call, 0) == 0;
  ok = ok && seccomp_load(filter) == 0;
  seccomp_release(filter);
  return ok;
}

int apply_landlock() {
#ifdef __NR_landlock_create_ruleset
  const long abi =
      syscall(__NR_landlock_create_ruleset, nullptr, 0, LANDLOCK_CREATE_RULESET_VERSION);
  if (abi < 1) return 0;
  // Every right but reading is handled, and no rule grants one back: reading is all that is left.
  struct landlock_ruleset_attr attr = {};
  attr.handled_access_fs =
      LANDLOCK_ACCESS_FS_EXECUTE | LANDLOCK_ACCESS_FS_WRITE_FILE | LANDLOCK_ACCESS_FS_REMOVE_DIR |
      LANDLOCK_ACCESS_FS_REMOVE_FILE | LANDLOCK_ACCESS_FS_MAKE_CHAR | LANDLOCK_ACCESS_FS_MAKE_DIR |
      LANDLOCK_ACCESS_FS_MAKE_REG | LANDLOCK_ACCESS_FS_MAKE_SOCK | LANDLOCK_ACCESS_FS_MAKE_FIFO |
      LANDLOCK_ACCESS_FS_MAKE_BLOCK | LANDLOCK_ACCESS_FS_MAKE_SYM;
  if (abi >= 2) attr.handled_access_fs |= kRefer;
  if (abi >= 3) attr.handled_access_fs |= kTruncate;
  const long ruleset = syscall(__NR_landlock_create_ruleset, &attr, sizeof attr, 0);
  if (ruleset < 0) return 0;
  const long done = syscall(__NR_landlock_restrict_self, ruleset, 0);
  close(static_cast<int>(ruleset));
  return done == 0 ? static_cast<int>(abi) : 0;
#else
  return 0;
#endif
}

}  // namespace

Confinement confine_process() {
  // Required by seccomp and Landlock for an unprivileged process; also stops set-uid programs.
  prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0);
  limit(RLIMIT_CORE, 0);  // a crash in the library leaves no core file behind
  limit(RLIMIT_FSIZE, 0);
  signal(SIGXFSZ, SIG_IGN);  // a write past the limit then fails with EFBIG instead of killing
  Confinement c;
  c.landlock_abi = apply_landlock();
  c.seccomp = apply_seccomp();
  return c;
}

}  // namespace hs
