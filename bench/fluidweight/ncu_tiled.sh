#!/bin/bash
# Nsight Compute of the tiled pipeline's setup and tile kernels (one launch each, after a warm
# call): the details page (throughput, occupancy, warp states) and per-instruction counters
# (SASS with instructions executed and stall samples), as CSV in $OUT for reading on the host.
# The fluidweight binary must keep its symbols (not stripped) for the per-instruction page.
set -u
D=${BIN_DIR:-.device-carry/new}
M=${MESHES:-.device-carry/meshes}
OUT=${OUT:-/tmp/fluidweight-out}
ncu --section SourceCounters --section WarpStateStats --section SpeedOfLight --section Occupancy \
  --section LaunchStats -k regex:"${KERNELS:-setup_kernel|tile_kernel}" --launch-skip 2 \
  --launch-count 2 -o "$OUT/rep" "$D/bin/fluidweight" "$M/${MESH:-armadillo}.obj" \
  --grid ${GRID:-1000} --device cuda --kernel ${KERNEL:-tiled:float32} --repeat 4 > /dev/null 2>&1
ncu -i "$OUT/rep.ncu-rep" --page details --csv > "$OUT/details.csv" 2>&1
ncu -i "$OUT/rep.ncu-rep" --page source --print-source sass --csv > "$OUT/sass.csv" 2>&1
rm -f "$OUT/rep.ncu-rep"
wc -l "$OUT"/*.csv
