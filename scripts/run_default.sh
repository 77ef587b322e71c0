#!/usr/bin/env bash
# Installs dependencies, builds pbf and runs the default scene (a dam break).
# In out/dam_break/: PLY frames, stats.csv, summary.json, images/ (a PNG per
# frame, rendered while simulating), dam_break.mp4 (ffmpeg), poster.png and
# stats.png (the statistics plotted with matplotlib).
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install_deps.sh
cmake --preset release
cmake --build --preset release -j "$(nproc)" --target pbf_cli
./build/release/pbf run scenes/dam_break.json --out out/dam_break "$@"
