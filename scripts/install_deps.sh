#!/usr/bin/env bash
# Installs hydrosoft's Debian 12 dependencies, only those that are missing.
# Usage: scripts/install_deps.sh            (everything: build, tests, postprocessing)
set -euo pipefail

packages=(
  build-essential cmake pkg-config git
  petsc-dev                 # PETSc 3.18 with MUMPS, hypre, HDF5, PTScotch (Open MPI flavour)
  libopenmpi-dev openmpi-bin
  libscotch-dev libptscotch-dev  # the parallel mesh partition (PTScotch, through PETSc)
  libeigen3-dev
  libsuitesparse-dev        # CHOLMOD: the control loop's background factorizations
  libhdf5-openmpi-dev
  gmsh libgmsh-dev
  libseccomp-dev            # confines the process that runs gmsh on untrusted meshes
  libyaml-cpp-dev nlohmann-json3-dev
  libgtest-dev googletest
  libopenblas0-pthread      # the reference BLAS makes MUMPS several times slower
  python3-numpy python3-h5py python3-yaml python3-matplotlib python3-paraview xvfb
  clang-format
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if ((${#missing[@]} == 0)); then
  echo "install_deps: all dependencies present"
  exit 0
fi

echo "install_deps: installing ${missing[*]}"
SUDO=""
if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
