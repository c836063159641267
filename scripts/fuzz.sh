#!/usr/bin/env bash
# The long fuzz campaign (docs/reliability.md, "Fuzzing"): thousands of mutated decks, meshes
# and overrides through hydrosoft --check, 5% of the fast ones also run for real (60 s each).
#   scripts/fuzz.sh [OUT] [CASES] [SEED]     (default: /tmp/hydrosoft_fuzz, 3000, 1)
# The report is OUT/report.json and OUT/cases.csv; each defect's reproducer OUT/defects/<id>/.
# Cases 0-299 of seed 1 are the ctest sample (fuzz_sample); the campaign starts after them.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-/tmp/hydrosoft_fuzz}
CASES=${2:-3000}
SEED=${3:-1}
HYDROSOFT=${HYDROSOFT:-build/bin/hydrosoft}
[[ -x $HYDROSOFT ]] || bash scripts/build.sh
exec /usr/bin/python3 tests/fuzz/fuzz.py --hydrosoft "$HYDROSOFT" --out "$OUT" --seed "$SEED" \
  --first 300 --cases "$CASES" --run-share 0.05 --jobs "${JOBS:-2}" --keep-time-limits
