#include "solvers/blas_threads.hpp"

#include <dlfcn.h>

#include <cstdlib>

namespace hs {

std::string limit_blas_threads() {
  for (const char* name : {"OPENBLAS_NUM_THREADS", "GOTO_NUM_THREADS", "OMP_NUM_THREADS"})
    if (const char* value = std::getenv(name))
      return std::string("as ") + name + "=" + value + " sets them";
  // Looked up rather than linked: the BLAS behind libblas.so.3 is whichever the machine's
  // alternatives choose, and only OpenBLAS has this call.
  using SetThreads = void (*)(int);
  auto set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  if (!set) return "the BLAS's own (not OpenBLAS)";
  set(1);
  return "1 (OpenBLAS; OPENBLAS_NUM_THREADS=N for more)";
}

}  // namespace hs
