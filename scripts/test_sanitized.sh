#!/usr/bin/env bash
# The serial tests (no MPI; tests/ labelled "serial" and the fluid-weight module's) built with
# AddressSanitizer and UndefinedBehaviorSanitizer in build-sanitize/ (or $SANITIZE_BUILD_DIR)
# and run; any sanitizer report fails a test (docs/reliability.md, "Sanitizers").
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
BUILD_DIR=${SANITIZE_BUILD_DIR:-build-sanitize}
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release -DHYDROSOFT_SANITIZE=address,undefined \
  -DFLUIDWEIGHT_CUDA=OFF
cmake --build "$BUILD_DIR" -j "$(nproc)" --target serial_tests
export OPENBLAS_NUM_THREADS=1
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=0:strict_string_checks=1:check_initialization_order=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export LSAN_OPTIONS=suppressions=$PWD/scripts/sanitizer_leaks.supp:print_suppressions=0
cd "$BUILD_DIR"
ctest --output-on-failure -j 2 --timeout 900 -L serial
ctest --output-on-failure -j 2 --timeout 900 -R '^fluidweight_test_' -E '^fluidweight_test_cuda$'
