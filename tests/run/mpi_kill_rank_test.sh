#!/usr/bin/env bash
# One rank of a distributed run killed for real (SIGKILL: no chance to clean
# up) in the middle of the dam break: mpirun stops the job with a non-zero
# status and names the rank; `--resume` on 2 ranks continues from the last
# checkpoint, and every frame equals the uninterrupted one-process run's,
# byte for byte (nothing lost, no half frame left).
# Usage: mpi_kill_rank_test.sh PBF WORKDIR SOURCE_DIR MPI_BUILT MPIRUN
set -euo pipefail
source "$(dirname "$0")/mpi_common.sh"

frames=24
run=(run "$src/scenes/dam_break.json" -q --set particle_radius=0.02 --no-plot --render none
     --frames $frames --checkpoint-every 4 --checkpoint-seconds 0)
"$pbf" "${run[@]}" --out "$work/straight" > /dev/null

"${mpi[@]}" -np 2 "$pbf" "${run[@]}" --out "$work/killed" > "$work/killed.log" 2>&1 &
job=$!
# Wait for the first checkpoint, then kill the rank that is not rank 0
# (the second pbf process mpirun started).
for _ in $(seq 1 600); do
    [ -e "$work/killed/checkpoint.pbfck" ] && break
    sleep 0.1
done
[ -e "$work/killed/checkpoint.pbfck" ] || { kill $job || true; fail "no checkpoint within 60 s"; }
victim=$(pgrep -f -n "pbf run .*$work/killed") || fail "no rank process found"
kill -9 "$victim"
status=0
wait $job || status=$?
[ $status -ne 0 ] || fail "mpirun exited 0 after a rank was killed"
grep -Eqi "rank [0-9]+.*(signal 9|killed)|signal 9 \(Killed\)" "$work/killed.log" ||
    { cat "$work/killed.log"; fail "the error does not name the killed rank"; }
echo "killed one rank (pid $victim): mpirun exited $status and said:"
grep -Ei "rank|signal" "$work/killed.log" | head -3
written=$(ls "$work/killed"/frame_*.ply | wc -l)
[ "$written" -lt $((frames + 1)) ] || fail "the job finished before the kill: nothing tested"
if ls -A "$work/killed" | grep -q '\.tmp'; then echo "(temporary files of the killed rank's last write remain; resume overwrites them)"; fi

"${mpi[@]}" -np 2 "$pbf" "${run[@]}" --resume --out "$work/killed" > "$work/resume.log" 2>&1 ||
    { cat "$work/resume.log"; fail "resume on 2 ranks failed"; }
count=0
for f in "$work/straight"/frame_*.ply; do
    cmp -s "$f" "$work/killed/$(basename "$f")" || fail "$(basename "$f") differs after the resume"
    count=$((count + 1))
done
[ $count -eq $((frames + 1)) ] || fail "$count frames compared"
echo "resumed on 2 ranks: $count frames bit-identical to one process ($written were written before the kill)"
echo "PASS"
