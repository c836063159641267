#!/usr/bin/env bash
# Strong scaling of a whole run (mesh, partition, set-up, assembly, solve, output) of the
# sphere of bench_sphere.yaml with the gamg preset: each mesh size on 1 to N ranks, one run
# each, every summary.json kept as OUTDIR/h<h>_np<n>.json. Made to run on the GPU machine from
# a bundle (scripts/device_bundle.sh: hydrosoft and mpirun on PATH, no Python needed there);
# bench/fem/strong_scaling_table.py turns the folder into the table of docs/benchmarks.md.
#   bash bench/fem/strong_scaling.sh DECK OUTDIR "0.05 0.035" "1 2 4 8 16"
set -uo pipefail
deck=$1 outdir=$2 sizes=$3 ranks=$4
mkdir -p "$outdir"
nproc >"$outdir/cores.txt"
grep -m1 "model name" /proc/cpuinfo >>"$outdir/cores.txt"
for h in $sizes; do
  for n in $ranks; do
    folder=$(mktemp -d)/run
    if mpirun -np "$n" hydrosoft "$deck" --set "mesh.parameters.h=$h" --set solver.preset=gamg \
      --set "output.folder=$folder" >"$outdir/h${h}_np$n.log" 2>&1; then
      cp "$folder/summary.json" "$outdir/h${h}_np$n.json"
    else
      echo "h=$h np=$n failed (see h${h}_np$n.log)"
    fi
    rm -rf "$(dirname "$folder")"
  done
done
