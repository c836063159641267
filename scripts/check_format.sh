#!/usr/bin/env bash
# Fails if a tracked C++ or CUDA file is not as clang-format (.clang-format) writes it; names
# the files. Fix with: git ls-files '*.cpp' '*.hpp' '*.cu' '*.cuh' | xargs clang-format -i
set -euo pipefail
cd "$(dirname "$0")/.."
git ls-files -z '*.cpp' '*.hpp' '*.cu' '*.cuh' | xargs -0 clang-format --dry-run -Werror
