#!/usr/bin/env bash
# H5Part files written by MPI ranks together (src/io/h5part.cpp), through
# tests/io/h5part_mpi_test.cpp: 4 ranks (uneven parts, one rank with none)
# and 1 rank write the same step, each run checking its file against the
# whole set and failures on every rank; then the two files' datasets are
# compared. The 4-rank file is opened in ParaView by clients.paraview_h5part.
# Usage: h5part_mpi_test.sh TEST_PROGRAM WORKDIR SOURCE_DIR MPI_BUILT MPIRUN
set -euo pipefail
source "$(dirname "$0")/../run/mpi_common.sh"
test_program=$pbf

"${mpi[@]}" -np 4 "$test_program" write "$work/np4" || fail "4 ranks"
"${mpi[@]}" -np 1 "$test_program" write "$work/np1" || fail "1 rank"
"$test_program" compare "$work/np4/frame_00012.h5part" "$work/np1/frame_00012.h5part" ||
    fail "4 ranks against 1"
echo "PASS: 4 ranks and 1 rank wrote the same H5Part step"
