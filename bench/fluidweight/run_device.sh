#!/bin/bash
# Runs on the GPU machine: the CUDA tests, then the benchmark (or its quick version with
# --quick). Binaries come prebuilt in BUILD (default build-cuda-alone); the meshes of
# docs/fluidweight.md in MESHES (default .device-carry/meshes). Output files go to $OUT.
set -u
BUILD=${BUILD:-build-cuda-alone}
MESHES=${MESHES:-.device-carry/meshes}
OUT=${OUT:-/tmp/fluidweight-out}
mkdir -p "$OUT"
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm,temperature.gpu --format=csv
lscpu | grep -E "Model name|^CPU\(s\)"
"$BUILD/tests/fluidweight_test_cuda" > "$OUT/test_cuda.log" 2>&1
echo "CUDA tests exit code $?"; grep -E "^\[  (PASSED|FAILED|SKIPPED) |FAILED TEST" "$OUT/test_cuda.log"
grep -B3 -A12 "Failure" "$OUT/test_cuda.log" | head -80
"$BUILD/bin/bench_fluidweight" --meshes "$MESHES" --out "$OUT/bench.jsonl" "$@" | tee "$OUT/bench.md"
