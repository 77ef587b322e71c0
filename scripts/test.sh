#!/usr/bin/env bash
# Installs dependencies, builds pbf (release preset) and runs the test suite.
# Usage: scripts/test.sh [--asan]   (--asan: AddressSanitizer + UBSan build instead)
set -euo pipefail
cd "$(dirname "$0")/.."

preset=release
if [ "${1:-}" = "--asan" ]; then preset=asan; fi

scripts/install_deps.sh
# The CUDA toolkit where it is installed but not on the PATH: the release
# build compiles the GPU backend with nvcc (PBF_CUDA, cmake/Gpu.cmake), so
# CI checks that it compiles (warnings as errors); the sanitizer build
# compiles only its CPU build (the asan preset sets PBF_CUDA=OFF).
if ! command -v nvcc > /dev/null && [ -x /usr/local/cuda/bin/nvcc ]; then
  export PATH=/usr/local/cuda/bin:$PATH
fi
cmake --preset "$preset"
cmake --build --preset "$preset" -j "$(nproc)"
ctest --preset "$preset" -j "$(nproc)"
