#!/usr/bin/env bash
# Strong scaling of a whole run (read, partition, set-up, assembly, solve, output) of the
# cantilever of bench/fem/cantilever_box.yaml on box meshes written by box_mesh (NXxNYxNZ
# cubes of 6 tetrahedra; 200x40x40 is 1.0M dofs, 430x86x86 9.8M): each size on each rank count,
# one run each, every summary.json kept as OUTDIR/h<size>_np<n>.json, the mesh writing time in
# OUTDIR/mesh_<size>.txt. Made to run on the GPU machine from a bundle
# (scripts/device_bundle.sh: hydrosoft, box_mesh and mpirun on PATH, no Python needed there);
# bench/fem/strong_scaling_table.py turns the folder into the table of docs/benchmarks.md.
#   HS_EXTRA="--set materials[0].model=linear_elastic" \
#     bash bench/fem/strong_scaling_box.sh OUTDIR "200x40x40" "1 2 4 8 16"
# (HS_EXTRA: further arguments of every run; HS_DECK: another deck on the same meshes, e.g.
# bench/contact/cantilever_on_floor.yaml, the beam landing on a floor)
set -uo pipefail
outdir=$1 sizes=$2 ranks=$3
deck=${HS_DECK:-$(cd "$(dirname "$0")" && pwd)/cantilever_box.yaml}
mkdir -p "$outdir"
nproc --all >"$outdir/cores.txt"  # --all: OMP_NUM_THREADS=1 makes plain nproc say 1
grep -m1 "model name" /proc/cpuinfo >>"$outdir/cores.txt"
work=$(mktemp -d)
for size in $sizes; do
  mesh=$work/box_$size.h5
  start=$(date +%s.%N)
  box_mesh ${size//x/ } "$mesh" >"$outdir/mesh_$size.txt"
  echo "seconds $(awk "BEGIN {print $(date +%s.%N) - $start}")" >>"$outdir/mesh_$size.txt"
  for n in $ranks; do
    if mpirun -np "$n" hydrosoft "$deck" --set "mesh.file=$mesh" ${HS_EXTRA:-} \
      --set "output.folder=$work/run" >"$outdir/h${size}_np$n.log" 2>&1; then
      cp "$work/run/summary.json" "$outdir/h${size}_np$n.json"
    else
      echo "$size np=$n failed (see h${size}_np$n.log)"
    fi
    rm -rf "$work/run"
  done
  rm -f "$mesh"
done
rm -rf "$work"
