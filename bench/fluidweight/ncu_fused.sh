#!/bin/bash
# Nsight Compute sections of one fused-kernel launch (sphere at 200^2, each tile of FUSED_TILES),
# for where the time goes: warp states, source counters (stall locations), occupancy.
set -u
D=${BIN_DIR:-.device-carry/fused}
M=${MESHES:-.device-carry/meshes}
OUT=${OUT:-/tmp/fluidweight-out}
for t in ${FUSED_TILES:-16 32}; do
  echo "== tile $t"
  FLUIDWEIGHT_FUSED_TILE=$t ncu --section SpeedOfLight --section Occupancy --section WarpStateStats \
    --section SourceCounters --section LaunchStats -k regex:fused --launch-skip 3 --launch-count 1 \
    "$D/bin/fluidweight" "$M/${MESH:-sphere}.obj" --grid ${GRID:-200} --device cuda \
    --kernel ${KERNEL:-fused:float32} --repeat 5 > "$OUT/ncu_tile$t.txt" 2>&1
  grep -E "Duration|Achieved Occupancy|Theoretical Occupancy|Registers Per|Shared Memory Config|Dynamic Shared|Warp Cycles Per Issued|Stall|stall|Issued Ipc" "$OUT/ncu_tile$t.txt" | head -40
done
