// The tests that run the hydrosoft executable start it as a child process under /bin/sh.
#pragma once

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <set>
#include <string>
#include <vector>

namespace hs::testing {

// The children started and not yet waited for. A test that stops at a failed ASSERT leaves
// its child running; when the test program ends, each one left gets SIGTERM (mpiexec passes it
// on to its ranks), 5 s to stop, then SIGKILL: no run outlives the test program that started
// it (a 2-rank run left alone once spun both cores for 40 minutes).
class Children {
 public:
  ~Children() {
    // Only a child still running (waitpid 0): one reaped elsewhere is left alone, whatever
    // process has its number now.
    std::vector<pid_t> running;
    for (const pid_t pid : pids_)
      if (waitpid(pid, nullptr, WNOHANG) == 0) {
        kill(pid, SIGTERM);
        running.push_back(pid);
      }
    for (const pid_t pid : running) {
      int left = 500;  // 5 s
      while (left-- > 0 && waitpid(pid, nullptr, WNOHANG) == 0) usleep(10000);
      if (left < 0) {
        kill(pid, SIGKILL);
        waitpid(pid, nullptr, 0);
      }
    }
  }
  std::set<pid_t> pids_;
};

inline Children& children() {
  static Children all;
  return all;
}

// Starts `command` under /bin/sh (exec'd: the process id is the command's, so that a signal
// sent to it reaches the command).
inline pid_t start(const std::string& command) {
  const pid_t pid = fork();
  if (pid == 0) {
    execl("/bin/sh", "sh", "-c", ("exec " + command).c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  children().pids_.insert(pid);
  return pid;
}

// The exit status of a process started by start() (-1: killed by a signal, or not ours).
inline int wait_for(pid_t pid) {
  int status = 0;
  const pid_t waited = waitpid(pid, &status, 0);
  children().pids_.erase(pid);
  if (waited != pid || !WIFEXITED(status)) return -1;
  return WEXITSTATUS(status);
}

inline int run(const std::string& command) { return wait_for(start(command)); }

}  // namespace hs::testing
