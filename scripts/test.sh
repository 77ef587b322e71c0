#!/usr/bin/env bash
# Installs dependencies, builds pbf (release preset) and runs the test suite.
# Usage: scripts/test.sh [--asan]   (--asan: AddressSanitizer + UBSan build instead)
set -euo pipefail
cd "$(dirname "$0")/.."

preset=release
if [ "${1:-}" = "--asan" ]; then preset=asan; fi

scripts/install_deps.sh
cmake --preset "$preset"
cmake --build --preset "$preset" -j "$(nproc)"
ctest --preset "$preset" -j "$(nproc)"
