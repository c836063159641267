#!/bin/bash
# Tiled kernel, for timing only: graph replays with Steps 3-4 and/or Step 5 left out
# (FLUIDWEIGHT_TILE_PHASES: 0 neither, 1 raster, 2 resolve, 3 both).
set -u
BUILD=${BUILD:-build-cuda-alone}
M=${MESHES:-.device-carry/meshes}
for mesh in "$@"; do
  for grid in 200 1000; do
    line="$mesh $grid:"
    for p in 0 1 2 3; do
      t=$(FLUIDWEIGHT_TILE_PHASES=$p FLUIDWEIGHT_REPLAYS=200 "$BUILD/bin/fluidweight" "$M/$mesh" \
        --grid $grid --device cuda --kernel tiled:float32 2>&1 >/dev/null | sed -E 's/graph replay median //')
      line="$line  phases $p: $t"
    done
    echo "$line"
  done
done
