// The child writes one answer to a pipe and ends with _exit: the lines for the user (tell_user),
// each as 'L', its length in 8 bytes and its text, then a kind byte ('M' a mesh, 'I' an input
// error, 'E' another error) and the encoded mesh or the message. _exit, because
// the child is a copy of an MPI process: it must not run MPI's or PETSc's exit handlers, nor
// flush the parent's buffered output a second time.
#include "mesh/gmsh_process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <iostream>
#include <new>
#include <string_view>
#include <vector>

#include "common/confinement.hpp"
#include "common/deck_reader.hpp"
#include "common/error.hpp"
#include "common/interrupt.hpp"
#include "mesh/mesh_wire.hpp"

namespace hs {
namespace {

int answer_fd = -1;             // the child's end of the pipe
std::string answer_file;        // the mesh file, for the terminate handler's message
std::vector<std::string> told;  // the child's lines for the user, sent with its answer
size_t told_dropped = 0;        // beyond kMaxRelayedLines
bool in_child = false;

void write_all(int fd, const std::string& bytes) {
  for (size_t done = 0; done < bytes.size();) {
    const ssize_t n = write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;  // the parent is gone: nobody to answer
    done += static_cast<size_t>(n);
  }
}

[[noreturn]] void answer(char kind, const std::string& payload) {
  if (told_dropped > 0)
    told.push_back("hydrosoft: " + answer_file + ": " + std::to_string(told_dropped) +
                   " more lines not shown");
  std::string bytes;
  for (const std::string& line : told) {
    const uint64_t size = line.size();
    bytes += 'L';
    bytes.append(reinterpret_cast<const char*>(&size), sizeof size);
    bytes += line;
  }
  write_all(answer_fd, bytes + std::string(1, kind) + payload);
  _exit(0);
}

// The lines ahead of the answer's kind byte, written to standard error; the rest of `bytes`.
// The bytes come from a process that read untrusted input: a line is printed with its control
// characters written out, and a record that does not fit is no answer.
std::string_view write_told_lines(std::string_view bytes, const std::string& file) {
  size_t lines = 0;
  while (!bytes.empty() && bytes[0] == 'L') {
    uint64_t size = 0;
    if (bytes.size() < 1 + sizeof size)
      throw InputError(file + ": gmsh's process gave an answer that is not one");
    std::memcpy(&size, bytes.data() + 1, sizeof size);
    bytes.remove_prefix(1 + sizeof size);
    if (size > bytes.size())
      throw InputError(file + ": gmsh's process gave an answer that is not one");
    if (++lines <= kMaxRelayedLines + 1)
      std::cerr << printable(std::string(bytes.substr(0, size))) << "\n";
    bytes.remove_prefix(size);
  }
  std::cerr.flush();
  return bytes;
}

// What the exception in flight says: gmsh 4.8 throws its errors as strings.
std::string what_was_thrown() {
  if (const std::exception_ptr error = std::current_exception()) {
    try {
      std::rethrow_exception(error);
    } catch (const std::string& text) {
      return text;
    } catch (const std::exception& e) {
      return e.what();
    } catch (...) {
    }
  }
  return "an error of unknown kind";
}

// gmsh's meshers run inside OpenMP regions, which an exception cannot leave: a gmsh error
// raised there (General.AbortOnError 2 throws it) reaches std::terminate. In the child that is
// still an answer: the error, as the input error it is.
[[noreturn]] void on_terminate() { answer('I', answer_file + ": gmsh: " + what_was_thrown()); }

// gmsh's Exit command calls exit(): the child answers before the exit handlers it inherited
// (MPI's, HDF5's, a leak checker's) run in a copy of the run.
void on_exit() {
  answer('I', answer_file + ": gmsh was told to exit before reading it to the end");
}

// The child keeps its pipe and `keep`. Standard input (which may carry the run's control
// targets) reads nothing; standard output and error go nowhere, since the run's error is one
// line and what gmsh or the C library print on a failure (a heap corruption's abort) would add
// lines to it; the descriptors of the parent's MPI connections, output and lock files close.
void detach_descriptors(int fd, std::vector<int> keep) {
  const int in = open("/dev/null", O_RDONLY | O_CLOEXEC),
            out = open("/dev/null", O_WRONLY | O_CLOEXEC);
  if (in >= 0) dup2(in, 0);
  if (out >= 0) {
    dup2(out, 1);
    dup2(out, 2);
  }
  keep.push_back(fd);
  std::sort(keep.begin(), keep.end());
  unsigned from = 3;
  for (int k : keep) {
    if (k < static_cast<int>(from)) continue;
    if (k > static_cast<int>(from)) close_range(from, static_cast<unsigned>(k) - 1, 0);
    from = static_cast<unsigned>(k) + 1;
  }
  close_range(from, ~0U, 0);
}

[[noreturn]] void run_child(int fd, const std::string& file, const std::function<Mesh()>& work,
                            const GmshProcess& how) {
  prctl(PR_SET_PDEATHSIG, SIGKILL);  // never outlive the run
  for (int s : {SIGTERM, SIGINT, SIGPIPE}) signal(s, SIG_DFL);
  // A fault kills the child, and the parent names the signal: the handlers the run installed
  // (PETSc's prints a stack and calls MPI_Abort, a sanitizer's reports) have no place in it.
  for (int s : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) signal(s, SIG_DFL);
  detach_descriptors(fd, how.keep);
  answer_fd = fd;
  answer_file = file;
  in_child = true;
  std::set_terminate(on_terminate);
  std::atexit(on_exit);
  if (how.confined) confine_process();
  try {
    answer('M', encode_mesh(work()));
  } catch (const InputError& e) {
    answer('I', e.what());
  } catch (const std::bad_alloc&) {
    answer('I', file +
                    ": gmsh ran out of memory reading it (a file that claims more than it "
                    "holds, or a mesh too large for this machine)");
  } catch (const std::exception& e) {
    answer('E', e.what());
  } catch (...) {  // nothing may leave the child: it would unwind the parent's copied stack
    answer('I', file + ": gmsh: " + what_was_thrown());
  }
}

// The child's answer, read while watching for SIGTERM and SIGINT: on one, the child is killed
// and Interrupted thrown.
std::string read_answer(int fd, pid_t child) {
  std::string bytes;
  char buffer[1 << 16];
  for (;;) {
    if (const int signal = interrupt_signal()) {
      kill(child, SIGKILL);
      waitpid(child, nullptr, 0);
      close(fd);
      throw Interrupted(signal);
    }
    struct pollfd p = {fd, POLLIN, 0};
    if (poll(&p, 1, 100) <= 0) continue;  // a timeout, or EINTR: look at the flag again
    const ssize_t n = read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    bytes.append(buffer, static_cast<size_t>(n));
  }
  close(fd);
  return bytes;
}

int wait_for(pid_t child) {
  int status = 0;
  while (waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  return status;
}

}  // namespace

Mesh run_gmsh_process(const std::string& file, const std::function<Mesh()>& work,
                      const GmshProcess& how) {
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0)
    throw std::runtime_error(file + ": cannot start gmsh's process: " + std::strerror(errno));
  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);
  const pid_t parent = getpid();
  const pid_t child = fork();
  if (child < 0) {
    close(fds[0]);
    close(fds[1]);
    throw std::runtime_error(file + ": cannot start gmsh's process: " + std::strerror(errno));
  }
  if (child == 0) {
    close(fds[0]);
    if (getppid() != parent) _exit(1);  // the run ended before the death signal was set
    run_child(fds[1], file, work, how);
  }
  close(fds[1]);
  const std::string answer_bytes = read_answer(fds[0], child);
  const int status = wait_for(child);
  if (WIFSIGNALED(status)) {
    const int signal = WTERMSIG(status);
    throw InputError(file + ": gmsh died of signal " + std::to_string(signal) + " (" +
                     strsignal(signal) +
                     ") while reading it: the file is damaged or made to crash gmsh");
  }
  if (answer_bytes.empty())
    throw InputError(file + ": gmsh ended (exit status " +
                     std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) +
                     ") without reading it to the end");
  const std::string_view bytes = write_told_lines(answer_bytes, file);
  if (bytes.empty()) throw InputError(file + ": gmsh's process gave an answer that is not one");
  const std::string_view payload = bytes.substr(1);
  switch (bytes[0]) {
    case 'M':
      return decode_mesh(payload, file);
    case 'I':
      throw InputError(std::string(payload));
    case 'E':
      throw std::runtime_error(std::string(payload));
    default:
      throw InputError(file + ": gmsh's process gave an answer that is not one");
  }
}

void tell_user(const std::string& line) {
  if (!in_child) {
    std::cerr << printable(line) << std::endl;
  } else if (told.size() < kMaxRelayedLines) {
    told.push_back(line);
  } else {
    ++told_dropped;
  }
}

}  // namespace hs
