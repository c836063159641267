#!/bin/bash
# Runs on the GPU machine: the CUDA tests of BUILD, then the issue's target cases
# (bench_fluidweight --targets) for each binary folder given (default: BUILD/bin), each with
# the tiled kernel's grid settings of TILE_BLOCKS (FLUIDWEIGHT_TILE_BLOCKS values, default
# "0"), then prefix-graph stage times (stages_device.sh's method) of BUILD for a few cases.
# Output files go to $OUT.
set -u
BUILD=${BUILD:-build-cuda-alone}
M=${MESHES:-.device-carry/meshes}
OUT=${OUT:-/tmp/fluidweight-out}
mkdir -p "$OUT"
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm,temperature.gpu --format=csv,noheader
if [ "${TESTS:-1}" = 1 ]; then
  "$BUILD/tests/fluidweight_test_cuda" > "$OUT/test_cuda.log" 2>&1
  echo "CUDA tests exit code $?"; grep -E "^\[  (PASSED|FAILED|SKIPPED) |FAILED TEST" "$OUT/test_cuda.log"
  grep -B3 -A12 "Failure" "$OUT/test_cuda.log" | head -60
fi
for dir in ${BINS:-$BUILD/bin}; do
  for tb in ${TILE_BLOCKS:-0}; do
    echo "== $dir FLUIDWEIGHT_TILE_BLOCKS=$tb"
    FLUIDWEIGHT_TILE_BLOCKS=$tb "$dir/bench_fluidweight" --meshes "$M" --targets \
      --out "$OUT/targets_$(basename "$(dirname "$dir")")_$tb.jsonl" | grep -E "^\|" | grep -v "case\|---"
  done
done
for c in "armadillo.obj 1000" "armadillo.obj 1500" "sphere 200"; do
  set -- $c
  mesh="$M/$1"; [ "$1" = sphere ] && mesh="$M/sphere.obj"
  [ -f "$mesh" ] || continue
  line="$1 $2 tiled:float32 prefixes:"
  for k in 1 2 3 4; do
    t=$(FLUIDWEIGHT_TILE_BLOCKS=${STAGE_BLOCKS:-0} FLUIDWEIGHT_GRAPH_STAGES=$k FLUIDWEIGHT_REPLAYS=200 \
      "$BUILD/bin/fluidweight" "$mesh" --grid $2 --device cuda --kernel tiled:float32 2>&1 >/dev/null \
      | sed -E 's/graph replay median //')
    line="$line $k: $t"
  done
  echo "$line"
done
