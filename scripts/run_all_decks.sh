#!/usr/bin/env bash
# Runs every deck of input/ with one hydrosoft binary on 2 MPI ranks, each into its own folder:
#   bash scripts/run_all_decks.sh BIN OUTDIR
# gives OUTDIR/<deck>/summary.json (with the fields) for each input/<deck>.yaml, the run's
# standard output and error in OUTDIR/<deck>.log and the wall time of each deck in
# OUTDIR/timings.txt. Two such folders are compared with scripts/compare_summaries.py.
# A deck that fails is reported and the others still run; the exit status is 1 if any failed.
set -uo pipefail
if [[ $# -ne 2 ]]; then
  echo "usage: $0 BIN OUTDIR" >&2
  exit 2
fi
bin=$(realpath "$1")
outdir=$(realpath -m "$2")
repo=$(cd "$(dirname "$0")/.." && pwd)
[[ -x $bin ]] || { echo "$0: '$bin' is not an executable" >&2; exit 2; }
mkdir -p "$outdir"
export OPENBLAS_NUM_THREADS=1
mpirun_flags=(--oversubscribe -np 2)
[[ $(id -u) -eq 0 ]] && mpirun_flags=(--allow-run-as-root "${mpirun_flags[@]}")
failed=0
: >"$outdir/timings.txt"
for deck in "$repo"/input/*.yaml; do
  name=$(basename "$deck" .yaml)
  start=$(date +%s.%N)
  if mpirun "${mpirun_flags[@]}" "$bin" "$deck" --set "output.folder=$outdir/$name" \
    >"$outdir/$name.log" 2>&1; then
    status=ok
  else
    status="FAILED (exit $?, see $outdir/$name.log)"
    failed=1
  fi
  seconds=$(echo "$(date +%s.%N) - $start" | bc)
  printf '%-24s %8.1f s  %s\n' "$name" "$seconds" "$status" | tee -a "$outdir/timings.txt"
done
exit $failed
