#!/usr/bin/env bash
# The pictures of docs/gallery.md: every deck of input/ run on 2 ranks into RUNS/<deck>
# (scripts/run_all_decks.sh makes that folder), then its last output step drawn by
# postprocess/render.py into OUT (default docs/figures/gallery), coloured by displacement.
#   bash scripts/run_all_decks.sh build/bin/hydrosoft /tmp/runs
#   bash postprocess/make_gallery.sh /tmp/runs [OUT]
set -euo pipefail
runs=$1
here=$(cd "$(dirname "$0")" && pwd)
out=${2:-$here/../docs/figures/gallery}
mkdir -p "$out"
for deck in "$here"/../input/*.yaml; do
  name=$(basename "$deck" .yaml)
  if [[ ! -f $runs/$name/summary.json ]]; then
    echo "make_gallery.sh: no run of $name in $runs" >&2
    exit 1
  fi
  /usr/bin/python3 "$here/render.py" "$runs/$name" --out "$out" --size 640x380
done
