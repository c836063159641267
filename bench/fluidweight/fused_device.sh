#!/bin/bash
# Runs on the GPU machine: the CUDA tests of BIN_DIR (default .device-carry/fused, with
# tests/ and bin/ built on the host), the targets (tiled and fused), the tiled/fused comparison
# (bench_fluidweight --fused), and the sphere at 200^2 with each fused tile (8, 16, 32) through
# the command line's replays. Output files go to $OUT.
set -u
D=${BIN_DIR:-.device-carry/fused}
M=${MESHES:-.device-carry/meshes}
OUT=${OUT:-/tmp/fluidweight-out}
mkdir -p "$OUT"
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm,temperature.gpu --format=csv,noheader
if [ "${TESTS:-1}" = 1 ]; then
  start=$(date +%s)
  "$D/tests/fluidweight_test_cuda" ${GTEST:-} > "$OUT/test_cuda.log" 2>&1
  echo "CUDA tests exit code $? ($(( $(date +%s) - start )) s)"
  grep -E "^\[  (PASSED|FAILED|SKIPPED) |FAILED TEST" "$OUT/test_cuda.log"
  grep -B3 -A12 "Failure" "$OUT/test_cuda.log" | head -60
fi
if [ "${TILES:-1}" = 1 ]; then
  for c in "sphere 200" "sphere 1000"; do
    set -- $c
    for k in tiled:float32 fused:float32 fused:float64; do
      for t in ${FUSED_TILES:-16}; do
        r=$(FLUIDWEIGHT_FUSED_TILE=$t FLUIDWEIGHT_REPLAYS=200 "$D/bin/fluidweight" "$M/$1.obj" \
          --grid $2 --device cuda --kernel $k 2>&1 >/dev/null | tr '\n' ' ')
        echo "$1 $2 $k tile $t: $r"
        [ "${k%%:*}" = tiled ] && break
      done
    done
  done
fi
if [ "${PHASES:-1}" = 1 ]; then
  # Prefixes of the fused kernel (FLUIDWEIGHT_TILE_PHASES): 8 the launch alone, 64 ten cluster
  # barriers, 16 up to the cluster's first barrier (box), 32 up to the vertex table, 7 also
  # the last barrier and the sums (no Step 2), 0 also Step 2 and the rounds without testing
  # candidates, 1 also Steps 3-4, 3 everything; for each cluster shape of CLUSTERS.
  for case in ${CASES:-sphere:200}; do
    for cl in ${CLUSTERS:-auto 1,1 4,1}; do
      line="${case/:/ } fused:float32 cluster $cl phases"
      for ph in 8 64 16 32 7 0 1 3; do
        r=$(FLUIDWEIGHT_FUSED_CLUSTER=$([ $cl = auto ] || echo $cl) FLUIDWEIGHT_TILE_PHASES=$ph \
          FLUIDWEIGHT_REPLAYS=200 "$D/bin/fluidweight" "$M/${case%%:*}.obj" --grid ${case##*:} \
          --device cuda --kernel fused:float32 2>&1 >/dev/null | sed -E 's/graph replay median //')
        line="$line $ph: $r"
      done
      echo "$line"
    done
  done
fi
[ "${TARGETS:-1}" = 1 ] && "$D/bin/bench_fluidweight" --meshes "$M" --targets \
  --out "$OUT/targets.jsonl" | grep -E "^\|" | grep -v "case\|---"
[ "${COMPARE:-1}" = 1 ] && "$D/bin/bench_fluidweight" --meshes "$M" --fused ${QUICK:-} \
  --out "$OUT/fused.jsonl" | tee "$OUT/fused.md" | grep -E "^\|"
exit 0
