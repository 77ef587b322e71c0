#!/usr/bin/env bash
# `pbf export usd` on bad input: a directory that is not a run, a run with a
# missing frame, a run with a truncated frame, and a truncated frame in a
# run that already has a stage, a root layer that cannot be written. Each
# must exit non-zero with a message that names the file, and leave the
# directory exactly as it was (no root layer, no per-frame layers, no
# temporary folder; an earlier stage untouched).
# Usage: bad_input_test.sh PBF RUN_DIR WORKDIR   (RUN_DIR: a run with a stage)
set -euo pipefail
pbf=$1
run=$2
work=$3
rm -rf "$work"
mkdir -p "$work"

# Every folder and every file's checksum below `dir`, hidden ones included.
snapshot() {
    (cd "$1" && find . -type d | sort && find . -type f -print0 | sort -z | xargs -0 md5sum)
}

# expect_failure NAME DIR PATTERN: the export fails, says PATTERN, changes nothing.
expect_failure() {
    local name=$1 dir=$2 pattern=$3
    local before after status=0
    before=$(snapshot "$dir")
    "$pbf" export usd "$dir" -q > "$work/$name.log" 2>&1 || status=$?
    cat "$work/$name.log"
    if [ "$status" -eq 0 ]; then
        echo "FAIL: $name: pbf export usd exited with 0"
        exit 1
    fi
    if ! grep -q -- "$pattern" "$work/$name.log"; then
        echo "FAIL: $name: the message does not say '$pattern'"
        exit 1
    fi
    after=$(snapshot "$dir")
    if [ "$before" != "$after" ]; then
        echo "FAIL: $name: the directory changed:"
        diff <(echo "$before") <(echo "$after") || true
        exit 1
    fi
    echo "$name: exit status $status, names the file, nothing written"
}

# A copy of the run without its stage.
copy_run() {
    cp -r "$run" "$1"
    rm -rf "$1/run.usda" "$1/run_usd"
}

mkdir -p "$work/not_a_run"
cp "$run/frame_00000.ply" "$work/not_a_run/"
expect_failure not_a_run "$work/not_a_run" "not_a_run/summary.json: missing"

copy_run "$work/missing"
rm "$work/missing/frame_00003.ply"
expect_failure missing_frame "$work/missing" "missing/frame_00003.ply: missing"

copy_run "$work/truncated"
head -c 300 "$run/frame_00005.ply" > "$work/truncated/frame_00005.ply"
expect_failure truncated_frame "$work/truncated" "truncated/frame_00005.ply: file is shorter"

# The same in a run with a stage: the failed export leaves the old one whole.
cp -r "$run" "$work/with_stage"
head -c 300 "$run/frame_00005.ply" > "$work/with_stage/frame_00005.ply"
expect_failure truncated_with_stage "$work/with_stage" "with_stage/frame_00005.ply: file is shorter"

# The root layer cannot be replaced (here a folder is in its place): the new
# per-frame layers are taken back out and the old ones put back.
cp -r "$run" "$work/root_fails"
rm "$work/root_fails/run.usda"
mkdir "$work/root_fails/run.usda"
expect_failure root_not_writable "$work/root_fails" "root_fails/run.usda: cannot rename"

if "$pbf" export usd "$work/no_such_directory" -q > "$work/none.log" 2>&1; then
    echo "FAIL: a missing directory exported"
    exit 1
fi
grep -q "no_such_directory: no such directory" "$work/none.log"
echo "usd bad input: all checks passed"
