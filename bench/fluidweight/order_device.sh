#!/bin/bash
# Runs on the GPU machine: version 14's tile order made within the call
# (FLUIDWEIGHT_TILE_ORDER_SAME_CALL=1; NEW built with results/v14_same_call_order.patch applied,
# the version tried and dropped, NOTES.md) against the previous call's order (the default) and the
# grid's order (FLUIDWEIGHT_TILE_ORDER=0, what a first call gets), with BASE's binaries (version
# 13) as a same-run reference: the CUDA tests of NEW,
# then ROUNDS rounds of bench_fluidweight --targets alternating the four, then prefix graphs of
# the armadillo at 1000^2 and 1500^2 in both orders. Before that, with BENCH_REPEATS=k, k more
# runs of BASE's whole benchmark (run_device.sh's) for medians over runs. Output files go to $OUT.
set -u
BASE=${BASE:-.device-carry/t1}
NEW=${NEW:-.device-carry/t2}
M=${MESHES:-.device-carry/meshes}
OUT=${OUT:-/tmp/fluidweight-out}
mkdir -p "$OUT"
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm,temperature.gpu --format=csv,noheader
grep -m1 -E "^cpu family" /proc/cpuinfo; grep -m1 -E "^model\s" /proc/cpuinfo
echo "extensions: $(grep -o -w -E 'avx512f|avx512_fp16|amx_tile|avx512_vnni|avx512_bf16' /proc/cpuinfo | sort -u | tr '\n' ' ')"
for r in $(seq 1 "${BENCH_REPEATS:-0}"); do
  start=$(date +%s)
  "$BASE/bin/bench_fluidweight" --meshes "$M" --out "$OUT/bench_run$((r + 1)).jsonl" > /dev/null
  echo "benchmark run $((r + 1)) exit code $? ($(( $(date +%s) - start )) s)"
done
start=$(date +%s)
"$NEW/tests/fluidweight_test_cuda" > "$OUT/test_cuda.log" 2>&1
echo "CUDA tests exit code $? ($(( $(date +%s) - start )) s)"
grep -E "^\[  (PASSED|FAILED|SKIPPED) |FAILED TEST" "$OUT/test_cuda.log"
grep -B3 -A12 "Failure" "$OUT/test_cuda.log" | head -60
: > "$OUT/order.jsonl"
for round in $(seq 1 "${ROUNDS:-2}"); do
  for v in base previous same grid; do
    case $v in
      base) bin=$BASE; env=;;
      previous) bin=$NEW; env=;;
      same) bin=$NEW; env=FLUIDWEIGHT_TILE_ORDER_SAME_CALL=1;;
      grid) bin=$NEW; env=FLUIDWEIGHT_TILE_ORDER=0;;
    esac
    env $env "$bin/bin/bench_fluidweight" --meshes "$M" --targets --out "$OUT/t.jsonl" \
      | grep -E "tiled" | sed "s/^/| $v $round /"
    sed "s/^{/{\"variant\": \"$v\", \"round\": $round, /" "$OUT/t.jsonl" >> "$OUT/order.jsonl"
  done
done
rm -f "$OUT/t.jsonl"
for c in "armadillo.obj 1000" "armadillo.obj 1500"; do
  set -- $c
  for v in previous same; do
    line="$1 $2 tiled:float32 $v prefixes:"
    for k in 2 3 4; do
      t=$( [ $v = same ] && export FLUIDWEIGHT_TILE_ORDER_SAME_CALL=1; \
        FLUIDWEIGHT_GRAPH_STAGES=$k FLUIDWEIGHT_REPLAYS=200 "$NEW/bin/fluidweight" "$M/$1" \
        --grid $2 --device cuda --kernel tiled:float32 2>&1 >/dev/null | sed -E 's/graph replay median //')
      line="$line $k: $t"
    done
    echo "$line"
  done
done
exit 0
