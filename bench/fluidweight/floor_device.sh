#!/bin/bash
# Runs on the GPU machine: builds the cuda/ tree, then times the pipeline skeletons
# (pipeline_floor) on the issue's target cases, then the real pipeline's targets and stage
# prefixes in the same lease (targets_device.sh without tests). Output files go to $OUT.
set -u
BUILD=${BUILD:-/tmp/b}
M=${MESHES:-.device-carry/meshes}
OUT=${OUT:-/tmp/fluidweight-out}
mkdir -p "$OUT"
cmake -S cuda -B "$BUILD" -DCMAKE_BUILD_TYPE=Release > "$OUT/cmake.log" 2>&1 &&
  cmake --build "$BUILD" -j16 --target pipeline_floor bench_fluidweight fluidweight \
    >> "$OUT/cmake.log" 2>&1 || { tail -30 "$OUT/cmake.log"; exit 1; }
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv,noheader
# CASES: "mesh grid cavities" items separated by commas.
CASES=${CASES:-sphere.obj 200 1,sphere.obj 200 4,armadillo.obj 200 1,armadillo.obj 1000 1,armadillo.obj 1500 1}
IFS=, read -r -a cases <<< "$CASES"
for round in 1 2; do
  for c in "${cases[@]}"; do
    set -- $c
    for tile in ${TILES:-16}; do "$BUILD/bin/pipeline_floor" "$M/$1" "$2" "$3" "$tile"; done
  done
done 2>&1 | tee "$OUT/pipeline_floor.txt"
[ "${TARGETS:-1}" = 1 ] || exit 0
TESTS=0 BUILD="$BUILD" MESHES="$M" OUT="$OUT" bash bench/fluidweight/targets_device.sh
