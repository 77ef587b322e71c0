#!/usr/bin/env bash
# Builds the libFuzzer harnesses (preset `fuzz`: clang, ASan + UBSan) and runs
# each for a fixed time on a seed corpus: the shipped scenes (scenes/), and
# small PLY files, override lists and a checkpoint (fuzz/corpus/). Crashes land in
# build/fuzz/artifacts/; the last lines of each log give the executions run.
# Usage: scripts/fuzz.sh [SECONDS_PER_HARNESS] [HARNESS...]   (default: 60 s, all)
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=${1:-60}
shift || true
harnesses=("$@")
if [ ${#harnesses[@]} -eq 0 ]; then harnesses=(scene override ply checkpoint); fi

scripts/install_deps.sh --clang
cmake --preset fuzz
cmake --build --preset fuzz -j "$(nproc)" --target fuzz_scene fuzz_override fuzz_ply fuzz_checkpoint

out=build/fuzz/run
mkdir -p "$out/artifacts"
status=0
for h in "${harnesses[@]}"; do
    corpus="$out/corpus/$h"
    mkdir -p "$corpus"
    dict=()
    if [ -f "fuzz/$h.dict" ]; then dict=(-dict="fuzz/$h.dict"); fi
    seeds=("fuzz/corpus/$h")
    if [ "$h" = scene ]; then seeds=(scenes); fi  # the shipped scenes are the seeds
    echo "fuzz.sh: fuzz_$h for $seconds s"
    # The first corpus directory collects new inputs; the seeds are read only.
    if ! build/fuzz/fuzz/fuzz_"$h" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
        -max_len=65536 -print_final_stats=1 -artifact_prefix="$out/artifacts/$h-" "${dict[@]}" \
        "$corpus" "${seeds[@]}" > "$out/$h.log" 2>&1; then
        echo "fuzz.sh: fuzz_$h FOUND A CRASH: see $out/$h.log and $out/artifacts/"
        status=1
    fi
    runs=$(grep -o 'stat::number_of_executed_units: [0-9]*' "$out/$h.log" | grep -o '[0-9]*$' || echo "?")
    echo "fuzz.sh: fuzz_$h: $runs inputs in $seconds s, corpus $(ls "$corpus" | wc -l) files"
done
exit $status
