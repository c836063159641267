#!/usr/bin/env bash
# The long fuzz campaign (docs/reliability.md, "Fuzzing the input"): thousands of mutated
# decks, meshes and overrides through hydrosoft --check, 5% of the fast ones also run for real
# (60 s each); thousands of mutated surface files through fluidweight; and the families of
# tests/fuzz/families.py (.geo merges, binary .msh, .h5 meshes, checkpoints, full disks,
# interactive clients, linked lock folders), 10% of them on 2 ranks.
#   scripts/fuzz.sh [OUT] [CASES] [SEED] [SURFACES]
#     (default: /tmp/hydrosoft_fuzz, 3000, 1, 2000; JOBS=N cases at a time, default 2;
#     FAMILIES="geo:700 binmsh:500 ..." the family cases, each NAME:COUNT, "" for none;
#     RANKS_SHARE=0.1 the share of family cases run on 2 ranks)
# The report is OUT/report.json and OUT/cases.csv; each defect's reproducer OUT/defects/<id>/.
# Cases 0-49 and surface cases s0-s29 of seed 1 are the ctest sample (fuzz_sample), the first
# cases of each family its own (fuzz_sample_new); the campaign starts after them (family cases
# from 100). Needs only the executables, mpiexec (or mpirun) for the 2-rank cases and
# /usr/bin/python3's standard library: HYDROSOFT=path/to/hydrosoft (fluidweight beside it, or
# FLUIDWEIGHT=path); mount for the full-disk cases' tmpfs where the user may (else they limit
# the file size instead).
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-/tmp/hydrosoft_fuzz}
CASES=${2:-3000}
SEED=${3:-1}
SURFACES=${4:-2000}
FAMILIES=${FAMILIES-geo:700 binmsh:500 h5mesh:500 checkpoint:500 disk:300 interactive:300 lock:300}
HYDROSOFT=${HYDROSOFT:-build/bin/hydrosoft}
FLUIDWEIGHT=${FLUIDWEIGHT:-$(dirname "$HYDROSOFT")/fluidweight}
[[ -x $HYDROSOFT && -x $FLUIDWEIGHT ]] || bash scripts/build.sh
family_args=()
for family in $FAMILIES; do family_args+=(--family "$family:100"); done
exec /usr/bin/python3 tests/fuzz/fuzz.py --hydrosoft "$HYDROSOFT" --fluidweight "$FLUIDWEIGHT" \
  --out "$OUT" --seed "$SEED" --first 50 --cases "$CASES" --surfaces-first 30 \
  --surfaces "$SURFACES" --run-share 0.05 "${family_args[@]}" --ranks-share "${RANKS_SHARE:-0.1}" \
  --jobs "${JOBS:-2}" --keep-time-limits
