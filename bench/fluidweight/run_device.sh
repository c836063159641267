#!/bin/bash
# Runs on the GPU machine from the repository root: configures and builds cuda/ with CUDA in
# BUILD, runs its tests, then the benchmark. Arguments go to bench_fluidweight (--quick,
# --targets, --fused). Tests: ctest when GoogleTest was found there; otherwise the test
# binaries in TESTS (a host build's tests/ folder, carried; the CLI test is skipped, it names the
# host's paths). The meshes of docs/fluidweight.md are read from MESHES (default
# .device-carry/meshes: copy /work/shared/meshes there and carry it); absent ones are skipped.
# Output files go to $OUT. The one-thread CPU figures are taken on the machine's last core (the
# benchmark pins its thread there).
set -u
BUILD=${BUILD:-build-fw-device}
TESTS=${TESTS:-}
MESHES=${MESHES:-.device-carry/meshes}
OUT=${OUT:-/tmp/fluidweight-out}
mkdir -p "$OUT"
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
lscpu | grep -E "Model name|^CPU\(s\)"
cmake -S cuda -B "$BUILD" -DCMAKE_BUILD_TYPE=Release > "$OUT/build.log" 2>&1 &&
  cmake --build "$BUILD" -j "$(nproc)" >> "$OUT/build.log" 2>&1 ||
  { tail -40 "$OUT/build.log"; exit 1; }
grep -E "fluidweight: " "$OUT/build.log"
failed=0
if [ -x "$BUILD/tests/fluidweight_test_cuda" ]; then
  (cd "$BUILD" && ctest --output-on-failure) > "$OUT/tests.log" 2>&1 || failed=1
  grep -E "tests passed|Failed|\*\*\*" "$OUT/tests.log"
elif [ -n "$TESTS" ]; then
  for t in "$TESTS"/fluidweight_test_*; do
    [ "${t##*/}" = fluidweight_test_cli ] && continue
    "$t" > "$OUT/${t##*/}.log" 2>&1 || failed=1
    echo "${t##*/}: $(grep -E '^\[  (PASSED|FAILED|SKIPPED) ' "$OUT/${t##*/}.log" | tr '\n' ' ')"
  done
else
  echo "no tests: GoogleTest not found here and no TESTS folder given"
fi
[ $failed = 0 ] || { grep -h -B3 -A12 "Failure" "$OUT"/*.log | head -80; exit 1; }
"$BUILD/bin/bench_fluidweight" --meshes "$MESHES" --out "$OUT/bench.jsonl" "$@" > "$OUT/bench.md"
echo "benchmark exit code $?"
grep -E "^(\||#)" "$OUT/bench.md"
