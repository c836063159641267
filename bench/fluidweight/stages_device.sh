#!/bin/bash
# Graph replay times of each pipeline's prefixes (FLUIDWEIGHT_GRAPH_STAGES=k keeps the first k
# kernels), so that differences give each kernel's share; then Nsight Compute's kernel
# durations. Usage: stages_device.sh MESH... (files in $MESHES).
set -u
BUILD=${BUILD:-build-cuda-alone}
M=${MESHES:-.device-carry/meshes}
for mesh in "$@"; do
  for grid in 200 1000; do
    for kernel in tiled:float32 tiled:float64 leveraging:float32; do
      line="$mesh $grid $kernel:"
      for k in 1 2 3 4; do
        t=$(FLUIDWEIGHT_GRAPH_STAGES=$k FLUIDWEIGHT_REPLAYS=200 "$BUILD/bin/fluidweight" "$M/$mesh" \
          --grid $grid --device cuda --kernel $kernel 2>&1 >/dev/null | sed -E 's/graph replay median //')
        line="$line  $k:$t"
      done
      echo "$line"
    done
  done
done
