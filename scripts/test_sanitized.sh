#!/usr/bin/env bash
# The tests built with AddressSanitizer and UndefinedBehaviorSanitizer in build-sanitize/ (or
# $SANITIZE_BUILD_DIR) and run. `scripts/test_sanitized.sh` (CI) runs the slice: those labelled
# `slice` (the paths that read untrusted input, tests/CMakeLists.txt), the fluid-weight
# module's, the serial tests of the three concerns whose code changed most lately
# (scripts/changed_concerns.sh; $SLICE_CONCERNS, a CMake list or `all`, overrides) and a slice
# of the fuzz sample on the sanitized executable.
# `scripts/test_sanitized.sh full` (before a release) runs every test: the MPI ones on 1 and 2
# ranks (the distribution's on 3 and 4 too) and all that run the executable. Any sanitizer
# report fails (docs/reliability.md, "Sanitizers").
set -euo pipefail
SCOPE=${1:-slice}
cd "$(dirname "$0")/.."
case $SCOPE in
  # The slice leaves out UndefinedBehaviorSanitizer's pointer checks (AddressSanitizer reports
  # a null or out-of-bounds access itself; a misaligned one is not an error on x86-64; vptr
  # checks casts the code makes with dynamic_cast), which took 40 % of the sanitized build,
  # and leak checks where MPI runs (MPI_LEAKS, below).
  slice) TARGET=slice_tests TESTS=slice MPI_TESTS=(-L slice -LE serial -E '_np1$') FUZZ_CASES=20
    CONCERNS=${SLICE_CONCERNS:-$(bash scripts/changed_concerns.sh)} MPI_LEAKS=0
    EXCEPT=alignment,null,object-size,pointer-overflow,vptr ;;
  full) TARGET=all_tests TESTS=all MPI_TESTS=(-L 'mpi|app' -E 'mpi_test_mesh_distribute_np[34]')
    FUZZ_CASES=50 CONCERNS=all MPI_LEAKS=1 EXCEPT= ;;
  *) echo "usage: $0 [slice|full]" >&2 && exit 2 ;;
esac
echo "test_sanitized.sh: $SCOPE; serial test programs built whole: $CONCERNS"
SECONDS=0
bash scripts/install_deps.sh
BUILD_DIR=${SANITIZE_BUILD_DIR:-build-sanitize}
# -O1, not Release's -O3: the sanitizers' instrumentation made -O3 compile 3.3 times as long
# as the plain build, -O1 1.4 times (docs/reliability.md, "Sanitizers"); NDEBUG as shipped.
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release -DHYDROSOFT_SANITIZE=address,undefined \
  -DCMAKE_CXX_FLAGS_RELEASE="-O1 -DNDEBUG" -DCMAKE_C_FLAGS_RELEASE="-O1 -DNDEBUG" \
  -DHYDROSOFT_SANITIZE_EXCEPT="$EXCEPT" -DFLUIDWEIGHT_CUDA=OFF -DHYDROSOFT_TEST_SCOPE="$TESTS" \
  -DHYDROSOFT_SLICE_CONCERNS="$CONCERNS"
cmake --build "$BUILD_DIR" -j "$(nproc)" --target "$TARGET"
built=$SECONDS
BUILD_DIR=$(cd "$BUILD_DIR" && pwd)
SOURCE_DIR=$PWD

# AddressSanitizer's and LeakSanitizer's reports go to files (one a process, children of the
# tests and mpiexec's ranks too), which are printed and fail the run at the end: a report in a
# child whose exit status a test does not check is not lost. Exit status 86 marks a report.
REPORTS=$BUILD_DIR/sanitizer_reports
rm -rf "$REPORTS" && mkdir -p "$REPORTS"
ASAN_COMMON="detect_leaks=1:abort_on_error=0:strict_string_checks=1:check_initialization_order=1:\
exitcode=86:log_path=$REPORTS/asan"
# UndefinedBehaviorSanitizer stops the program at its first report, on standard error (it does
# not follow log_path when built with AddressSanitizer); hence also the search of ctest's log.
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1:exitcode=86
export LSAN_OPTIONS=suppressions=$PWD/scripts/sanitizer_leaks.supp:print_suppressions=0
export OPENBLAS_NUM_THREADS=1 OMPI_MCA_rmaps_base_oversubscribe=1

failed=0
cd "$BUILD_DIR"
run_ctest() {
  ctest --output-on-failure -j 2 --timeout 900 "$@" || failed=1
  if grep -n "runtime error:" Testing/Temporary/LastTest.log; then failed=1; fi
}
export ASAN_OPTIONS=$ASAN_COMMON
run_ctest -L serial  # what the scope built: in the slice, the untrusted input's and the chosen concerns'
run_ctest -R '^fluidweight_test_' -E '^fluidweight_test_cuda$'
# Where MPI runs, leaks are checked with the whole stack of each allocation: Open MPI unloads
# its components in MPI_Finalize, so the frames of an allocation made in one cannot be named
# when LeakSanitizer reports at exit, and the suppressions name instead the Open MPI function
# the allocation was made under (ompi_mpi_init, ...; scripts/sanitizer_leaks.supp), further
# up. The system's libraries have no frame pointers, so only the slow unwinder reaches it: 3
# times the run time. The slice checks leaks in the serial tests only; `full` everywhere.
if [ "$MPI_LEAKS" = 1 ]; then
  export ASAN_OPTIONS=$ASAN_COMMON:fast_unwind_on_malloc=0
else
  export ASAN_OPTIONS=$ASAN_COMMON:detect_leaks=0
fi
run_ctest "${MPI_TESTS[@]}"

# The fuzz sample (tests/fuzz/) on the sanitized executable: its first 20 cases (the slice) or
# all 50 (full) through --check, 10 % of the fast ones also run for real (2 of the slice's 20,
# as many as the 40 cases at 5 % the slice had before). Its address-space limit would stop AddressSanitizer (which reserves terabytes
# of shadow memory): --memory-mb 0 lifts it, and the sanitizer's own limits take its place (a
# too large allocation returns null, so std::bad_alloc as without the sanitizer).
ASAN_OPTIONS="$ASAN_OPTIONS:allocator_may_return_null=1:max_allocation_size_mb=4096:hard_rss_limit_mb=4096" \
  /usr/bin/python3 "$SOURCE_DIR/tests/fuzz/fuzz.py" --hydrosoft bin/hydrosoft --out "$BUILD_DIR/fuzz_sanitized" \
  --seed 1 --cases "$FUZZ_CASES" --run-share 0.1 --jobs 2 --memory-mb 0 --check-timeout 180 --run-timeout 180 ||
  failed=1

if compgen -G "$REPORTS/*" > /dev/null; then
  for f in "$REPORTS"/*; do echo "== $f" && cat "$f"; done
  failed=1
fi
echo "test_sanitized.sh: installs and build ${built} s, tests $((SECONDS - built)) s"
exit $failed
