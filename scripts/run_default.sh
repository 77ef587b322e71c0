#!/usr/bin/env bash
# Installs dependencies, builds pbf and runs the default scene (a dam break):
# PLY frames, stats.csv and summary.json land in out/dam_break/.
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install_deps.sh
cmake --preset release
cmake --build --preset release -j "$(nproc)" --target pbf_cli
./build/release/pbf run scenes/dam_break.json --out out/dam_break "$@"
