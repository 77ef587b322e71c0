#!/usr/bin/env bash
# `pbf run` killed for real, then resumed: SIGKILL (no chance to clean up) and
# SIGTERM (stops cleanly with a checkpoint) in the middle of a run, then
# `--resume`; every frame file (and bodies.csv, for a scene with rigid
# bodies) must equal the uninterrupted run's byte for byte, and the VTK
# collection particles.pvd must list every frame once.
# Usage: kill_resume_test.sh PBF SCENE WORKDIR [EXTRA_RUN_ARGUMENTS...]
#   e.g. --device cuda-on-cpu: the same on another device.
set -euo pipefail
pbf=$1
scene=$2
work=$3
shift 3
rm -rf "$work"
mkdir -p "$work"
frames=40
args=(run "$scene" --frames "$frames" -q --set particle_radius=0.015 --checkpoint-every 2
      --checkpoint-seconds 0 --vtk "$@")

"$pbf" "${args[@]}" --out "$work/straight" > /dev/null

# Starts a run, waits until frame 5 exists (so a checkpoint of frame 4 exists),
# sends the signal, and checks the exit status.
interrupt() {
    local signal=$1 dir=$2 expected=$3
    "$pbf" "${args[@]}" --out "$dir" > "$dir.log" 2>&1 &
    local pid=$! waited=0
    until [ -e "$dir/frame_00005.ply" ]; do
        sleep 0.02
        waited=$((waited + 1))
        if [ "$waited" -gt 6000 ]; then echo "FAIL: run made no progress"; kill -KILL "$pid"; exit 1; fi
    done
    kill "-$signal" "$pid"
    local status=0
    wait "$pid" || status=$?
    if [ -e "$dir/frame_$(printf %05d "$frames").ply" ]; then
        echo "FAIL: the run finished before the $signal arrived; the test needs a longer run"
        exit 1
    fi
    if [ "$status" -ne "$expected" ]; then
        echo "FAIL: exit status $status after SIG$signal, expected $expected"
        cat "$dir.log"
        exit 1
    fi
    echo "SIG$signal: stopped after $(ls "$dir"/frame_*.ply | wc -l) frame files, exit status $status"
}

compare() {
    local dir=$1
    local count
    count=$(ls "$work/straight"/frame_*.ply | wc -l)
    [ "$count" -eq $((frames + 1)) ] || { echo "FAIL: $count frames in the straight run"; exit 1; }
    for f in "$work/straight"/frame_*.ply "$work/straight"/frame_*.vtu; do
        cmp "$f" "$dir/$(basename "$f")" || { echo "FAIL: $(basename "$f") differs after resume"; exit 1; }
    done
    cmp "$work/straight/particles.pvd" "$dir/particles.pvd" ||
        { echo "FAIL: particles.pvd after resume differs from the uninterrupted run's"; cat "$dir/particles.pvd"; exit 1; }
    if [ -e "$work/straight/bodies.csv" ]; then
        cmp "$work/straight/bodies.csv" "$dir/bodies.csv" || { echo "FAIL: bodies.csv differs after resume"; exit 1; }
    fi
    if ls -A "$dir" | grep -q '\.tmp'; then echo "FAIL: temporary files left in $dir"; exit 1; fi
}

interrupt KILL "$work/killed" 137
"$pbf" "${args[@]}" --out "$work/killed" --resume > /dev/null
compare "$work/killed"
echo "SIGKILL + --resume: $((frames + 1)) frames bit-identical"

interrupt TERM "$work/terminated" 143
grep -q "stopped by signal 15 after frame" "$work/terminated.log" || { echo "FAIL: no stop message"; exit 1; }
grep -q -- "--resume" "$work/terminated.log" || { echo "FAIL: no resume hint"; exit 1; }
"$pbf" "${args[@]}" --out "$work/terminated" --resume > /dev/null
compare "$work/terminated"
echo "SIGTERM + --resume: $((frames + 1)) frames bit-identical"
rm -rf "$work"
