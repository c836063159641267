#!/bin/bash
# Runs on the GPU machine (a copy of the working tree, no PETSc): builds cuda/ alone, then
# times the fluid-weight module on the cavity surfaces that run_benchmark.py --export-obj
# wrote to bench/cavity/surfaces/ (the cavities of the undeformed meshes, water, gravity as
# in the decks): CUDA (tiled kernel, float64, the solver's choice), the CPU fast path on
# all cores and pinned to one core (the solver runs it with one thread per owning rank).
# One JSON line per run goes to $OUT/gpu_fluidweight.jsonl.
set -u
OUT=${OUT:-/tmp/cavity-out}
BUILD=${BUILD:-build-cuda}
mkdir -p "$OUT"
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
lscpu | grep -E "Model name|^CPU\(s\)"
cmake -S cuda -B "$BUILD" -DCMAKE_BUILD_TYPE=Release > "$OUT/cmake.log" 2>&1 &&
  cmake --build "$BUILD" -j16 --target fluidweight >> "$OUT/cmake.log" 2>&1 ||
  { tail -40 "$OUT/cmake.log"; exit 1; }
FW="$BUILD/bin/fluidweight"
[ -x "$FW" ] || FW=$(find "$BUILD" -name fluidweight -type f -perm -u+x | head -1)
for mesh in bench/cavity/surfaces/*.obj; do
  case "$mesh" in *sphere*) g=0,0,-9.81 ;; *) g=0,-9.81,0 ;; esac
  common=(--grid 200 --rho 1000 --gravity $g --json)
  "$FW" "$mesh" "${common[@]}" --device cuda --repeat 50 | sed 's/}$/, "run": "cuda"}/'
  "$FW" "$mesh" "${common[@]}" --device cuda --kernel tiled:float32 --repeat 50 |
    sed 's/}$/, "run": "cuda float32"}/'
  "$FW" "$mesh" "${common[@]}" --device cpu --repeat 50 | sed 's/}$/, "run": "cpu all cores"}/'
  taskset -c 0 "$FW" "$mesh" "${common[@]}" --device cpu --repeat 20 |
    sed 's/}$/, "run": "cpu one core"}/'
done | tee "$OUT/gpu_fluidweight.jsonl"
