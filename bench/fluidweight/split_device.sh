#!/bin/bash
# Runs on the GPU machine: where each pipeline's time goes. For each case, every stage launched
# alone between events (FLUIDWEIGHT_KERNEL_TIMES) and graph replays of the pipeline's prefixes
# (FLUIDWEIGHT_GRAPH_STAGES=k: the first k kernels). Cases: CASES="mesh:grid:kernel ...".
set -u
BUILD=${BUILD:-build-cuda-alone}
M=${MESHES:-.device-carry/meshes}
nvidia-smi --query-gpu=name,driver_version,clocks.sm --format=csv,noheader
for c in ${CASES:-armadillo.obj:200:triangle_parallel:float32 armadillo.obj:200:leveraging:float32 \
  armadillo.obj:200:tiled:float32 armadillo.obj:1000:tiled:float32 sphere.obj:200:tiled:float32 \
  sphere.obj:200:fused:float32 sphere.obj:200:triangle_parallel:float32}; do
  IFS=: read -r mesh grid kernel prec <<< "$c"
  echo "== $mesh $grid $kernel:$prec"
  FLUIDWEIGHT_KERNEL_TIMES=1 "$BUILD/bin/fluidweight" "$M/$mesh" --grid "$grid" --device cuda \
    --kernel "$kernel:$prec" --repeat 3 2>&1 >/dev/null | sort -u | head -12
  line="prefixes:"
  for k in 1 2 3 4 5; do
    t=$(FLUIDWEIGHT_GRAPH_STAGES=$k FLUIDWEIGHT_REPLAYS=200 "$BUILD/bin/fluidweight" "$M/$mesh" \
      --grid "$grid" --device cuda --kernel "$kernel:$prec" 2>&1 >/dev/null | sed -E 's/graph replay median //')
    line="$line $k: $t"
  done
  echo "$line"
done
