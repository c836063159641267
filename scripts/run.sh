#!/usr/bin/env bash
# The main job: installs, builds, and runs hydrosoft on its default deck over 2 MPI ranks.
#   bash scripts/run.sh [DECK] [more hydrosoft arguments]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh hydrosoft  # the executable alone, not the tests and benchmarks
deck=${1:-input/cylinder_water.yaml}
shift || true
mpirun_flags=(--oversubscribe)
[[ $(id -u) -eq 0 ]] && mpirun_flags+=(--allow-run-as-root)
export OPENBLAS_NUM_THREADS=1
mpirun "${mpirun_flags[@]}" -np "${NP:-2}" build/bin/hydrosoft "$deck" "$@"
