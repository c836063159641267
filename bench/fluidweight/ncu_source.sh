#!/bin/bash
# Nsight Compute per-source-line counters of one fused-kernel launch (instructions executed,
# stall samples), written as CSV to $OUT for reading on the host.
set -u
D=${BIN_DIR:-.device-carry/fused}
M=${MESHES:-.device-carry/meshes}
OUT=${OUT:-/tmp/fluidweight-out}
for t in ${FUSED_TILES:-16}; do
  FLUIDWEIGHT_FUSED_TILE=$t ncu --section SourceCounters --section WarpStateStats -k regex:fused \
    --launch-skip 3 --launch-count 1 -o "$OUT/rep$t" \
    "$D/bin/fluidweight" "$M/${MESH:-sphere}.obj" --grid ${GRID:-200} --device cuda \
    --kernel ${KERNEL:-fused:float32} --repeat 5 > /dev/null 2>&1
  ncu -i "$OUT/rep$t.ncu-rep" --page source --print-source cuda --csv > "$OUT/src$t.csv" 2>&1
  ncu -i "$OUT/rep$t.ncu-rep" --page source --print-source sass --csv > "$OUT/sass$t.csv" 2>&1
  rm -f "$OUT/rep$t.ncu-rep"
  wc -l "$OUT/src$t.csv" "$OUT/sass$t.csv"; head -3 "$OUT/src$t.csv" | cut -c1-600
done
