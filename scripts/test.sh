#!/usr/bin/env bash
# The whole test suite: installs, builds with warnings as errors, checks the format of the
# C++ and CUDA files, and runs every test (serial and 1/2-rank MPI).
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS=0
bash scripts/build.sh all_tests  # what the tests run; the benchmarks are built by scripts/build.sh alone
bash scripts/check_format.sh
built=$SECONDS
export OPENBLAS_NUM_THREADS=1 OMPI_MCA_rmaps_base_oversubscribe=1
cd "${BUILD_DIR:-build}"
status=0
ctest --output-on-failure -j 2 --timeout 900 || status=$?
echo "scripts/test.sh: installs, build and format check ${built} s, tests $((SECONDS - built)) s"
exit $status
