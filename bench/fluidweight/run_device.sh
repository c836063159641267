#!/bin/bash
# Runs on the GPU machine: the CUDA tests, then the benchmark (or its quick version with
# --quick), then with TARGETS=1 the cases (--targets). Binaries come prebuilt in BUILD
# (default build-cuda-alone: BUILD/tests/fluidweight_test_cuda, BUILD/bin/bench_fluidweight);
# the meshes of docs/fluidweight.md in MESHES (default .device-carry/meshes). Output files go
# to $OUT. The one-thread CPU figures are taken on the machine's last core (the benchmark pins
# its thread there); the script prints which processor that is and its vector extensions.
set -u
BUILD=${BUILD:-build-cuda-alone}
MESHES=${MESHES:-.device-carry/meshes}
OUT=${OUT:-/tmp/fluidweight-out}
mkdir -p "$OUT"
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm,temperature.gpu --format=csv
lscpu | grep -E "Model name|^CPU\(s\)|Thread|MHz"
echo "vector extensions: $(grep -o -w -E 'avx2|avx512f|avx512bw|avx512vl|avx512cd' /proc/cpuinfo | sort -u | tr '\n' ' ')"
start=$(date +%s)
"$BUILD/tests/fluidweight_test_cuda" > "$OUT/test_cuda.log" 2>&1
echo "CUDA tests exit code $? ($(( $(date +%s) - start )) s)"; grep -E "^\[  (PASSED|FAILED|SKIPPED) |FAILED TEST" "$OUT/test_cuda.log"
grep -B3 -A12 "Failure" "$OUT/test_cuda.log" | head -80
start=$(date +%s)
"$BUILD/bin/bench_fluidweight" --meshes "$MESHES" --out "$OUT/bench.jsonl" "$@" > "$OUT/bench.md"
echo "benchmark exit code $? ($(( $(date +%s) - start )) s)"
if [ "${TARGETS:-0}" = 1 ]; then
  "$BUILD/bin/bench_fluidweight" --meshes "$MESHES" --targets --out "$OUT/targets.jsonl" \
    > "$OUT/targets.md"
fi
cat "$OUT/bench.md" "$OUT"/targets.md 2>/dev/null | grep -E "^(\||#|CPU|GPU)"
