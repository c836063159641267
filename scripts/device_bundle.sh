#!/usr/bin/env bash
# Packs a hydrosoft build made on this Debian 12 machine (CUDA included) with the Debian shared
# libraries it needs and Open MPI's launcher and plugins, so that it runs on a machine that has
# none of them (the project's GPU machine: a GPU, 16 cores, no PETSc, MPI or gmsh).
#
#   bash scripts/device_bundle.sh BUILD_DIR OUT_DIR [NAME ...]
#
# hydrosoft and fluidweight always go in; each NAME adds a program of BUILD_DIR/bin (box_mesh,
# bench_fluidweight, ...) or a test executable of BUILD_DIR/tests (mpi_test_solvers, ...), with the
# libraries it needs (the GPU benchmarks' bring cuSOLVER and cuBLAS: name them only when they
# are to run). input/ and meshes/ go in too. Writes OUT_DIR/part_aa, part_ab, ...: the
# bundle (xz) in parts of 40 MB, since the device tool carries at most 64 MiB a call. Send
# part_aa in one call (`cat .device-carry/part_aa > /tmp/p`) and the rest in the next one at
# once (the machine stays warm ~30 s), there:
#   cat /tmp/p .device-carry/part_a[b-z] | xz -dc | tar x -C /tmp/b && . /tmp/b/env.sh
# and then `mpirun -np N hydrosoft /tmp/b/proj/input/DECK.yaml` as here.
# The reference BLAS and LAPACK stand in for OpenBLAS (35 MB less): MUMPS's dense kernels are
# slower with them, so time GAMG, the assembly and the GPU with such a bundle, not MUMPS;
# HYDROSOFT_BUNDLE_BLAS=openblas packs OpenBLAS instead (one part more).
set -euo pipefail
if [[ $# -lt 2 ]]; then
  echo "usage: $0 BUILD_DIR OUT_DIR [NAME ...]" >&2
  exit 2
fi
build=$(readlink -f "$1")
out=$(readlink -m "$2")
shift 2
repo=$(cd "$(dirname "$0")/.." && pwd)
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
mkdir -p "$stage"/{bin,lib,ompi/lib,ompi/etc,ompi/pmix,proj} "$out"

# The libraries a binary loads, but those every Linux has, the GPU driver's and OpenBLAS.
copy_libraries() {
  local lib
  for lib in $(ldd "$1" | awk '/=>/ {print $3}'); do
    case $(basename "$lib") in
      libc.so* | libm.so* | libpthread.so* | libdl.so* | librt.so* | ld-linux* | libcuda.so* | \
        libopenblas.so*) ;;
      *) cp -nL "$lib" "$stage/lib/" ;;
    esac
  done
}
add_binary() {
  cp "$1" "$stage/bin/"
  strip "$stage/bin/$(basename "$1")" 2>/dev/null || true
  copy_libraries "$1"
}

for name in hydrosoft fluidweight "$@"; do
  if [[ -x $build/bin/$name ]]; then
    add_binary "$build/bin/$name"
  elif [[ -x $build/tests/$name ]]; then
    add_binary "$build/tests/$name"
  else
    echo "$0: no program $name in $build/bin or $build/tests" >&2
    exit 2
  fi
done
add_binary "$(readlink -f /usr/bin/mpirun)"
add_binary "$(command -v orted)"
mv "$stage/bin/orterun" "$stage/bin/mpirun" 2>/dev/null || true
ln -sf mpirun "$stage/bin/mpiexec"  # the machine may have an mpiexec of its own, of another Open MPI
if [[ ${HYDROSOFT_BUNDLE_BLAS:-reference} == openblas ]]; then  # for runs that time MUMPS
  openblas=/usr/lib/x86_64-linux-gnu/openblas-pthread
  cp -L "$openblas/libblas.so.3" "$openblas/liblapack.so.3" "$openblas/libopenblas.so.0" "$stage/lib/"
else
  cp -L /usr/lib/x86_64-linux-gnu/blas/libblas.so.3 /usr/lib/x86_64-linux-gnu/lapack/liblapack.so.3 \
    "$stage/lib/"
fi

# Open MPI finds its plugins, help texts and settings through OPAL_* (env.sh); transports for
# networks the machine has none of are left out.
cp -rL /usr/lib/x86_64-linux-gnu/openmpi/lib/openmpi3 "$stage/ompi/lib/"
(cd "$stage/ompi/lib/openmpi3" && rm -f ./*ucx* ./*ofi* ./*psm* ./*openib* ./*uct* ./*verbs* \
  ./*hcoll* ./*java*)
cp -rL /usr/share/openmpi "$stage/ompi/share"
cp /etc/openmpi/* "$stage/ompi/etc/"
cp -rL /usr/lib/x86_64-linux-gnu/pmix2/lib/pmix/. "$stage/ompi/pmix/"
for plugin in "$stage"/ompi/lib/openmpi3/*.so "$stage"/ompi/pmix/*.so; do
  copy_libraries "$plugin" 2>/dev/null || true
done
cp -r "$repo/input" "$repo/meshes" "$stage/proj/"

cat >"$stage/env.sh" <<'ENV'
# Sourced on the GPU machine: the bundle's libraries and Open MPI, as root, one BLAS thread.
B=${B:-/tmp/b}
export LD_LIBRARY_PATH=$B/lib OPAL_PREFIX=$B/ompi OPAL_LIBDIR=$B/ompi/lib \
  OPAL_PKGLIBDIR=$B/ompi/lib/openmpi3 OPAL_PKGDATADIR=$B/ompi/share \
  PMIX_MCA_mca_base_component_path=$B/ompi/pmix PATH=$B/bin:$PATH \
  PMIX_MCA_mca_base_component_show_load_errors=0 \
  OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1 \
  OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1
# Test binaries read input/ and meshes/ below the source folder compiled into them.
src=$(cat "$B/source_dir")
[ -e "$src" ] || { mkdir -p "$(dirname "$src")" && ln -s "$B/proj" "$src"; }
ENV
echo "$repo" >"$stage/source_dir"

rm -f "$out"/part_*
(cd "$stage" && tar cf - .) | xz -T0 -7 | split -b 40m - "$out/part_"
ls -l "$out"
