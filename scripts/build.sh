#!/usr/bin/env bash
# Installs what is missing, then configures and builds hydrosoft in build/ (or $BUILD_DIR):
# everything, or the targets named (`scripts/build.sh hydrosoft`). Warnings of the project's
# code are errors (the compiler is Debian 12's; HYDROSOFT_WERROR=OFF for another).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
BUILD_DIR=${BUILD_DIR:-build}
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release -DHYDROSOFT_WERROR="${HYDROSOFT_WERROR:-ON}"
targets=()
for target in "$@"; do targets+=(--target "$target"); done
cmake --build "$BUILD_DIR" -j "$(nproc)" "${targets[@]}"
