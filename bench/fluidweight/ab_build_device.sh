#!/bin/bash
# Runs on the GPU machine: builds the working tree's cuda/ (into /tmp/b1) and a previous
# version's (OLD_SRC, a folder holding cuda/ and bench/fluidweight/, e.g. made here by
# `git archive REV cuda bench/fluidweight | tar -x -C .device-carry/v0`; into $B0) side by
# side, runs the new build's CUDA tests, then ab_device.sh over CASES with both binaries and
# the VARIANTS given ("name=ENV=value,ENV2=value ...": the new binary under that environment), ROUNDS
# times, alternated; then, with TARGETS=1, bench_fluidweight --targets of both (twice each,
# alternated); with FUSED=1, bench_fluidweight --fused of the new build. OLD_TARGETS=" "
# builds and runs the previous version's tests too. MID_SRCS="name=folder ..." (folders like
# OLD_SRC) builds further versions into /tmp/bm_name, run under that name between old and new.
# Output files go to $OUT.
set -u
OLD_SRC=${OLD_SRC:-.device-carry/v0}
B0=${B0:-/tmp/b0}  # a fresh folder for each OLD_SRC (git archive keeps old file times)
OUT=${OUT:-/tmp/fluidweight-out}
mkdir -p "$OUT"
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm,temperature.gpu --format=csv,noheader
start=$(date +%s)
(cmake -S "$OLD_SRC/cuda" -B $B0 -DCMAKE_BUILD_TYPE=Release > "$OUT/build0.log" 2>&1 &&
  cmake --build $B0 -j8 ${OLD_TARGETS:---target fluidweight bench_fluidweight} \
    >> "$OUT/build0.log" 2>&1) &
(cmake -S cuda -B /tmp/b1 -DCMAKE_BUILD_TYPE=Release > "$OUT/build1.log" 2>&1 &&
  cmake --build /tmp/b1 -j8 >> "$OUT/build1.log" 2>&1) &
for m in ${MID_SRCS:-}; do
  (cmake -S "${m#*=}/cuda" -B "/tmp/bm_${m%%=*}" -DCMAKE_BUILD_TYPE=Release \
    > "/tmp/build_${m%%=*}.log" 2>&1 &&
    cmake --build "/tmp/bm_${m%%=*}" -j8 --target fluidweight bench_fluidweight \
      >> "/tmp/build_${m%%=*}.log" 2>&1) &
done
wait
echo "builds: $(( $(date +%s) - start )) s"
grep -E "error|warning" "$OUT/build1.log" | head -20
[ -x $B0/bin/fluidweight ] && [ -x /tmp/b1/bin/fluidweight ] || { tail -30 "$OUT"/build*.log; exit 1; }
start=$(date +%s)
/tmp/b1/tests/fluidweight_test_cuda > "$OUT/test_cuda.log" 2>&1
echo "CUDA tests exit code $? ($(( $(date +%s) - start )) s)"
grep -E "^\[  (PASSED|FAILED|SKIPPED) |FAILED TEST" "$OUT/test_cuda.log"
grep -B3 -A12 "Failure" "$OUT/test_cuda.log" | head -60
if [ -x $B0/tests/fluidweight_test_cuda ]; then
  $B0/tests/fluidweight_test_cuda > "$OUT/test_cuda_old.log" 2>&1
  echo "old CUDA tests exit code $?"; grep -E "^\[  (PASSED|FAILED) |FAILED TEST" "$OUT/test_cuda_old.log"
fi
BINS="old=$B0/bin/fluidweight"
for m in ${MID_SRCS:-}; do
  [ -x "/tmp/bm_${m%%=*}/bin/fluidweight" ] || { tail -20 "/tmp/build_${m%%=*}.log"; continue; }
  BINS="$BINS ${m%%=*}=/tmp/bm_${m%%=*}/bin/fluidweight"
done
BINS="$BINS new=/tmp/b1/bin/fluidweight"
for v in ${VARIANTS:-}; do
  name=${v%%=*}
  printf '#!/bin/sh\nexport %s\nexec /tmp/b1/bin/fluidweight "$@"\n' "$(echo "${v#*=}" | tr , ' ')" \
    > "/tmp/$name.sh"
  chmod +x "/tmp/$name.sh"
  BINS="$BINS $name=/tmp/$name.sh"
done
BINS="$BINS" bash bench/fluidweight/ab_device.sh | tee "$OUT/ab.txt"
if [ "${TARGETS:-0}" = 1 ]; then
  for r in 1 2; do
    for b in $B0 /tmp/b1; do
      $b/bin/bench_fluidweight --meshes "${MESHES:-.device-carry/meshes}" --targets \
        --out "$OUT/targets_$(basename $b)_$r.jsonl" | grep -E "^\|" | grep -v "case\|---\|CPU" |
        sed "s|^|$(basename $b) |"
    done
  done
fi
if [ "${FUSED:-0}" = 1 ]; then
  timeout 300 /tmp/b1/bin/bench_fluidweight --meshes "${MESHES:-.device-carry/meshes}" --fused \
    --out "$OUT/fused_b1.jsonl" > "$OUT/fused_b1.md"
  grep -E "^\|" "$OUT/fused_b1.md"
fi
