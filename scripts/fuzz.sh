#!/usr/bin/env bash
# The long fuzz campaign (docs/reliability.md, "Fuzzing"): thousands of mutated decks, meshes
# and overrides through hydrosoft --check, 5% of the fast ones also run for real (60 s each),
# and thousands of mutated surface files through fluidweight.
#   scripts/fuzz.sh [OUT] [CASES] [SEED] [SURFACES]
#     (default: /tmp/hydrosoft_fuzz, 3000, 1, 2000; JOBS=N cases at a time, default 2)
# The report is OUT/report.json and OUT/cases.csv; each defect's reproducer OUT/defects/<id>/.
# Cases 0-299 and surface cases s0-s99 of seed 1 are the ctest sample (fuzz_sample); the
# campaign starts after them. Needs only the executables and /usr/bin/python3's standard
# library: HYDROSOFT=path/to/hydrosoft (fluidweight beside it, or FLUIDWEIGHT=path).
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-/tmp/hydrosoft_fuzz}
CASES=${2:-3000}
SEED=${3:-1}
SURFACES=${4:-2000}
HYDROSOFT=${HYDROSOFT:-build/bin/hydrosoft}
FLUIDWEIGHT=${FLUIDWEIGHT:-$(dirname "$HYDROSOFT")/fluidweight}
[[ -x $HYDROSOFT && -x $FLUIDWEIGHT ]] || bash scripts/build.sh
exec /usr/bin/python3 tests/fuzz/fuzz.py --hydrosoft "$HYDROSOFT" --fluidweight "$FLUIDWEIGHT" \
  --out "$OUT" --seed "$SEED" --first 300 --cases "$CASES" --surfaces-first 100 \
  --surfaces "$SURFACES" --run-share 0.05 --jobs "${JOBS:-2}" --keep-time-limits
