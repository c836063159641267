// One BLAS thread per MPI rank unless the user chose otherwise. MUMPS's dense kernels are many
// small matrix products; OpenBLAS's own threads on them (one per core by default) gain nothing
// on an idle machine and, beside other work, wait on each other through cores that are not
// theirs: on the 2-core machine beside one busy process a run took 5.9 s with two threads
// against 2.6 s with one (docs/benchmarks.md, "BLAS threads"). OpenBLAS reads
// OPENBLAS_NUM_THREADS when it is loaded, before main(); this sets the count through its own
// call where the library is OpenBLAS.
#pragma once

#include <string>

namespace hs {

// Where none of OPENBLAS_NUM_THREADS, GOTO_NUM_THREADS and OMP_NUM_THREADS is set and the BLAS
// is OpenBLAS: its threads set to 1. Returns what was done, for the run's printout.
std::string limit_blas_threads();

}  // namespace hs
