#!/bin/bash
# Per-kernel GPU times with Nsight Compute (ncu serialises kernels and may lock clocks: use
# the numbers to compare kernels, the benchmark's graph replays for the real figures).
set -u
BUILD=${BUILD:-build-cuda-alone}
MESHES=${MESHES:-.device-carry/meshes}
OUT=${OUT:-/tmp/fluidweight-out}
i=0
for args in "$@"; do
  i=$((i + 1))
  echo "== $args"
  ncu --csv --metrics gpu__time_duration.sum,sm__warps_active.avg.pct_of_peak_sustained_active \
    "$BUILD/bin/fluidweight" $args --device cuda --repeat 2 > "$OUT/ncu$i.csv" 2>/dev/null
  python3 - "$OUT/ncu$i.csv" <<'PY'
import csv, sys
rows = [r for r in csv.DictReader(l for l in open(sys.argv[1]) if l.startswith('"'))]
seen = {}
for r in rows:
    name = r['Kernel Name'].split('(')[0].split('::')[-1]
    seen.setdefault(name, {})[r['Metric Name']] = r['Metric Value']
for name, m in seen.items():
    print(f"  {name:32s} {float(m['gpu__time_duration.sum'].replace(',', ''))/1000:8.1f} us  warps {m['sm__warps_active.avg.pct_of_peak_sustained_active']}%")
PY
done
