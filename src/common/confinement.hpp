// Confinement of a process that hands untrusted input to a library we cannot audit (gmsh
// parsing a .geo or .msh): from the call on, the process may read files, compute and write to
// the descriptors it already holds, and nothing else. It cannot start a program (so no shell
// command of a .geo runs, whatever way it is reached), open a network socket, or create,
// change or remove a file. The mechanisms are the kernel's (docs/reliability.md, "gmsh runs
// confined"): no_new_privs, a seccomp filter (libseccomp), a Landlock ruleset where the
// kernel has Landlock, and resource limits that stop file writes and core dumps where it has not.
#pragma once

namespace hs {

struct Confinement {
  bool seccomp = false;  // execve, execveat and socket fail with EPERM
  int landlock_abi = 0;  // > 0: writes, removals, new files and execution denied everywhere
};

// Confines the calling process for the rest of its life (it cannot be undone: meant for a
// child process). Every mechanism the kernel offers is applied; the result says which were.
// Throws nothing.
Confinement confine_process();

}  // namespace hs
