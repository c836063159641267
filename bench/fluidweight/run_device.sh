#!/bin/bash
# Runs on the GPU machine from the repository root: configures and builds cuda/ with CUDA,
# runs its tests (ctest), then the benchmark. Arguments go to bench_fluidweight (--quick,
# --targets, --fused). The meshes of docs/fluidweight.md are read from MESHES (default
# .device-carry/meshes: copy /work/shared/meshes there and carry it); absent meshes are skipped.
# Output files go to $OUT. The one-thread CPU figures are taken on the machine's last core (the
# benchmark pins its thread there); the script prints which processor that is.
set -u
BUILD=${BUILD:-build-fw-device}
MESHES=${MESHES:-.device-carry/meshes}
OUT=${OUT:-/tmp/fluidweight-out}
mkdir -p "$OUT"
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv,noheader
lscpu | grep -E "Model name|^CPU\(s\)"
echo "vector extensions: $(grep -o -w -E 'avx2|avx512f' /proc/cpuinfo | sort -u | tr '\n' ' ')"
cmake -S cuda -B "$BUILD" -DCMAKE_BUILD_TYPE=Release > "$OUT/build.log" 2>&1 &&
  cmake --build "$BUILD" -j "$(nproc)" >> "$OUT/build.log" 2>&1 ||
  { tail -40 "$OUT/build.log"; exit 1; }
(cd "$BUILD" && ctest --output-on-failure) > "$OUT/ctest.log" 2>&1
tests=$?
grep -E "tests passed|Passed|Failed|\*\*\*" "$OUT/ctest.log"
[ $tests = 0 ] || { grep -B3 -A12 "Failure" "$OUT/ctest.log" | head -80; exit 1; }
"$BUILD/bin/bench_fluidweight" --meshes "$MESHES" --out "$OUT/bench.jsonl" "$@" > "$OUT/bench.md"
echo "benchmark exit code $?"
grep -E "^(\||#)" "$OUT/bench.md"
