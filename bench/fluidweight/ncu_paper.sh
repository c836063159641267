set -u
M=.device-carry/meshes
for g in 200 1000; do
ncu --section WarpStateStats --section SpeedOfLight --section Occupancy --section LaunchStats --section MemoryWorkloadAnalysis \
  -k regex:"leveraging_kernel|column_kernel|reduce_kernel|setup_kernel" --launch-skip 4 --launch-count 4 -o "$OUT/rep$g" \
  build-cuda-alone/bin/fluidweight "$M/armadillo.obj" --grid $g --device cuda --kernel leveraging:float32 --repeat 3 > /dev/null 2>&1
ncu -i "$OUT/rep$g.ncu-rep" --page details --csv > "$OUT/details$g.csv" 2>&1
done
ncu --section SourceCounters -k regex:"leveraging_kernel|column_kernel" --launch-skip 2 --launch-count 2 -o "$OUT/src" \
  build-cuda-alone/bin/fluidweight "$M/armadillo.obj" --grid 1000 --device cuda --kernel leveraging:float32 --repeat 3 > /dev/null 2>&1
ncu -i "$OUT/src.ncu-rep" --page source --print-source sass --csv > "$OUT/sass.csv" 2>&1
rm -f $OUT/*.ncu-rep
wc -l $OUT/*.csv
