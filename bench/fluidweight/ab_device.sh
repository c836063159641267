#!/bin/bash
# Runs on the GPU machine: graph replay medians of the same cases with several fluidweight
# binaries, alternated (BINS="name=path ..."), ROUNDS times. CASES="mesh:grid:kernel:precision ...".
set -u
M=${MESHES:-.device-carry/meshes}
for round in $(seq ${ROUNDS:-2}); do
  for c in $CASES; do
    IFS=: read -r mesh grid kernel prec <<< "$c"
    line="$mesh $grid $kernel:$prec"
    for nb in $BINS; do
      t=$(FLUIDWEIGHT_REPLAYS=200 "${nb#*=}" "$M/$mesh" --grid "$grid" --device cuda \
        --kernel "$kernel:$prec" 2>&1 >/dev/null | sed -E 's/graph replay median //')
      line="$line | ${nb%%=*} $t"
    done
    echo "$line"
  done
done
