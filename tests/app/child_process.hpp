// The tests that run the hydrosoft executable start it as a child process under /bin/sh.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <string>

namespace hs::testing {

// Starts `command` under /bin/sh (exec'd: the process id is the command's, so that a signal
// sent to it reaches the command).
inline pid_t start(const std::string& command) {
  const pid_t pid = fork();
  if (pid == 0) {
    execl("/bin/sh", "sh", "-c", ("exec " + command).c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  return pid;
}

// The exit status of a process started by start() (-1: killed by a signal, or not ours).
inline int wait_for(pid_t pid) {
  int status = 0;
  if (waitpid(pid, &status, 0) != pid || !WIFEXITED(status)) return -1;
  return WEXITSTATUS(status);
}

inline int run(const std::string& command) { return wait_for(start(command)); }

}  // namespace hs::testing
