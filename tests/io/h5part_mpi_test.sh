#!/usr/bin/env bash
# H5Part files written by MPI ranks together (src/io/h5part.cpp), through
# tests/io/h5part_mpi_test.cpp: 4 ranks (uneven parts, one rank with none)
# and 1 rank write the same step, each run checking its file against the
# whole set and failures on every rank; then the two files' datasets are
# compared. The 4-rank file is opened in ParaView by clients.paraview_h5part.
# Then `pbf run --h5part` on 4 ranks (the sparse basin: a rank holds no
# particles at times): every frame's H5Part file, sorted by id, holds the
# particles of its PLY frame, and particles.h5part lists every frame.
# Usage: h5part_mpi_test.sh TEST_PROGRAM WORKDIR SOURCE_DIR MPI_BUILT MPIRUN PBF
set -euo pipefail
source "$(dirname "$0")/../run/mpi_common.sh"
test_program=$pbf
pbf_cli=$6

"${mpi[@]}" -np 4 "$test_program" write "$work/np4" || fail "4 ranks"
"${mpi[@]}" -np 1 "$test_program" write "$work/np1" || fail "1 rank"
"$test_program" compare "$work/np4/frame_00012.h5part" "$work/np1/frame_00012.h5part" ||
    fail "4 ranks against 1"
echo "PASS: 4 ranks and 1 rank wrote the same H5Part step"

"${mpi[@]}" -np 4 "$pbf_cli" run "$src/tests/data/mpi_basin.json" -q --no-plot --render none \
    --checkpoint-every 0 --checkpoint-seconds 0 --h5part --frames 6 --out "$work/run4" \
    > "$work/run4.log" 2>&1 || { cat "$work/run4.log"; fail "pbf run --h5part on 4 ranks"; }
[ -s "$work/run4/particles.h5part" ] || fail "no particles.h5part index"
count=0
for ply in "$work"/run4/frame_*.ply; do
    "$test_program" matches-ply "${ply%.ply}.h5part" "$ply" > /dev/null ||
        fail "${ply%.ply}.h5part does not hold the particles of $ply"
    count=$((count + 1))
done
[ "$count" -eq 7 ] || fail "$count frames, expected 7"
echo "PASS: pbf run on 4 ranks wrote $count H5Part frames holding the PLY frames' particles"
