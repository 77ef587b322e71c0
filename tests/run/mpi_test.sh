#!/usr/bin/env bash
# Distributed runs (docs/distributed.md) against one process, through the CLI:
#   * the dam break (the fluid crosses the tank: particles migrate between
#     key ranges and the cuts move) on 2 and 3 ranks writes the same PLY
#     frames as one process, byte for byte (bit-identical: see
#     src/backend/mpi/key_range_halo.hpp for why that holds; all ranks
#     write each frame at once), and the same stats.csv up to the
#     summation order of the reductions;
#   * a scene with an emitter, a solid, XSPH and vorticity confinement
#     (every halo exchange) on 2 ranks, also over TCP on loopback
#     (--mca btl tcp,self: the transport two hosts use);
#   * surface tension with adhesion (walls and a solid) on 2 ranks;
#   * a cube of water on 8 ranks: the same frames, a one-cell halo;
#   * a scene 10 km from the origin (the World's local frame), walls
#     driven by a prescribed motion, and water leaving through outlets, on
#     2 ranks;
#   * checkpoints, written by all ranks at once: the dam break's state in
#     them equals one process's byte for byte; 2 ranks stop at frame 8, 3
#     ranks and 1 process resume (each rank reading its share) to the end:
#     frames equal the uninterrupted one-process run's;
#   * summary.json has "ranks" and "rank_particles" adding up to "particles".
# Usage: mpi_test.sh PBF WORKDIR SOURCE_DIR MPI_BUILT MPIRUN
set -euo pipefail
source "$(dirname "$0")/mpi_common.sh"

# Byte comparison of every frame of two runs; prints the number compared.
same_frames() {
    local a=$1 b=$2 count=0
    for f in "$a"/frame_*.ply; do
        cmp -s "$f" "$b/$(basename "$f")" || fail "$b/$(basename "$f") differs from $f"
        count=$((count + 1))
    done
    [ "$count" -gt 0 ] || fail "no frames in $a"
    echo "$count"
}

# stats.csv: the columns of the state equal; sums (kinetic energy, average
# density error) to 1e-9 relative: the ranks' partial sums are added in
# another order than one process's blocks (double sums of float terms, so
# the reassociation error is ~1e-16 per term); timings are not compared.
same_stats() {
    python3 - "$1/stats.csv" "$2/stats.csv" <<'PY'
import csv, sys
a = list(csv.DictReader(open(sys.argv[1])))
b = list(csv.DictReader(open(sys.argv[2])))
assert len(a) == len(b) and len(a) > 1, f"{len(a)} vs {len(b)} rows"
exact = ["frame", "particles", "substeps", "iterations", "max_density_error", "escaped",
         "inside_solid", "max_speed"]
close = ["time", "avg_density_error", "kinetic_energy"]
for ra, rb in zip(a, b):
    for k in exact:
        assert ra[k] == rb[k], f"frame {ra['frame']}: {k} {ra[k]} vs {rb[k]}"
    for k in close:
        x, y = float(ra[k]), float(rb[k])
        assert abs(x - y) <= 1e-9 * max(abs(x), abs(y), 1e-30), f"frame {ra['frame']}: {k} {x} vs {y}"
PY
}

# The checkpoints' state (header fields and particle arrays; not the run's
# totals, which hold wall-clock times) equal, byte for byte: written by all
# ranks at once, each its part, it must be one process's file.
same_checkpoint_state() {
    python3 - "$1/checkpoint.pbfck" "$2/checkpoint.pbfck" <<'PY'
import struct, sys, zlib
def state(path):
    d = open(path, "rb").read()
    size, crc = struct.unpack_from("<QQ", d, 16)
    assert len(d) == 32 + size and zlib.crc32(d[32:]) == crc, f"{path}: bad size or CRC-32"
    at = 32 + 8
    at += 8 + struct.unpack_from("<Q", d, at)[0] + 4 + 8 + 8  # version, frame, time, next id
    # position, velocity (3 floats each), density, id (u64), solve acceleration (3 floats)
    for value_bytes in [4, 4, 4, 4, 4, 4, 4, 8, 4, 4, 4]:
        at += 8 + struct.unpack_from("<Q", d, at)[0] * value_bytes
    return d[32:at]
a, b = state(sys.argv[1]), state(sys.argv[2])
assert len(a) > 1000 and a == b, f"{len(a)} vs {len(b)} bytes of state"
PY
}

check_summary() {
    python3 - "$1/summary.json" "$2" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
ranks = int(sys.argv[2])
assert s["ranks"] == ranks, s["ranks"]
assert len(s["rank_particles"]) == ranks and sum(s["rank_particles"]) == s["particles"], s
# Load balance: every slab holds a fair share at the end.
mean = s["particles"] / ranks
assert all(abs(n - mean) <= 0.35 * mean for n in s["rank_particles"]), s["rank_particles"]
PY
}

base=(run "$src/scenes/dam_break.json" -q --set particle_radius=0.02 --no-plot --render none
      --checkpoint-every 0 --checkpoint-seconds 0)
dam=("${base[@]}" --frames 18)
"$pbf" "${dam[@]}" --out "$work/dam1" > /dev/null
for n in 2 3; do
    "${mpi[@]}" -np $n "$pbf" "${dam[@]}" --out "$work/dam$n" > "$work/dam$n.log" 2>&1 ||
        { cat "$work/dam$n.log"; fail "dam break on $n ranks failed"; }
    frames=$(same_frames "$work/dam1" "$work/dam$n")
    same_stats "$work/dam1" "$work/dam$n" || fail "stats.csv of $n ranks"
    same_checkpoint_state "$work/dam1" "$work/dam$n" || fail "checkpoint of $n ranks"
    check_summary "$work/dam$n" $n || fail "summary.json of $n ranks"
    echo "dam break, $n ranks: $frames frames and the checkpoint bit-identical to one process"
done
# The front must have crossed the tank (else nothing migrated).
python3 - "$work/dam1/frame_00018.ply" <<'PY' || fail "the dam break front did not cross the tank"
import struct, sys
data = open(sys.argv[1], "rb").read()
header_end = data.index(b"end_header\n") + len(b"end_header\n")
n = int([l for l in data[:header_end].split(b"\n") if l.startswith(b"element vertex")][0].split()[2])
xs = [struct.unpack_from("<f", data, header_end + 32 * i)[0] for i in range(n)]
assert max(xs) > 1.4, max(xs)
PY

# The accuracy options: the tolerance's stopping test sums over all ranks
# (exact fixed-point sums: the same iteration count as one process) and the
# warm start's accelerations migrate and are gathered with the particles;
# the run stops at frame 8 on 2 ranks and resumes on 3.
accurate=("${base[@]}" --set solver.max_density_error=0.002 --set solver.warm_start=0.8
          --set solver.over_relaxation=1.2)
"$pbf" "${accurate[@]}" --frames 12 --out "$work/acc1" > /dev/null
"${mpi[@]}" -np 2 "$pbf" "${accurate[@]}" --frames 8 --out "$work/acc2" > "$work/acc2.log" 2>&1 ||
    { cat "$work/acc2.log"; fail "accuracy options on 2 ranks failed"; }
"${mpi[@]}" -np 3 "$pbf" "${accurate[@]}" --frames 12 --resume --out "$work/acc2" > "$work/acc3.log" 2>&1 ||
    { cat "$work/acc3.log"; fail "accuracy options resumed on 3 ranks failed"; }
frames=$(same_frames "$work/acc1" "$work/acc2")
echo "tolerance + warm start + omega, 2 ranks -> resume on 3: $frames frames bit-identical"

pour=(run "$src/tests/data/mpi_pour.json" -q --no-plot --render none --checkpoint-every 0
      --checkpoint-seconds 0)
"$pbf" "${pour[@]}" --out "$work/pour1" > /dev/null
"${mpi[@]}" -np 2 "$pbf" "${pour[@]}" --out "$work/pour2" > "$work/pour2.log" 2>&1 ||
    { cat "$work/pour2.log"; fail "emitter scene on 2 ranks failed"; }
frames=$(same_frames "$work/pour1" "$work/pour2")
echo "emitter + solid + vorticity, 2 ranks: $frames frames bit-identical"
"$mpirun" --oversubscribe --allow-run-as-root --mca btl tcp,self --mca btl_tcp_if_include lo \
    -np 2 "$pbf" "${pour[@]}" --out "$work/pour_tcp" > "$work/pour_tcp.log" 2>&1 ||
    { cat "$work/pour_tcp.log"; fail "2 ranks over TCP failed"; }
frames=$(same_frames "$work/pour1" "$work/pour_tcp")
echo "over TCP (loopback), 2 ranks: $frames frames bit-identical"

# A 60 m x 4 m x 60 m basin (1.8e9 cells of the kernel radius) with water in
# two opposite corners: each rank holds only its cells; 2 and 4 ranks (one
# with no particles between the corners' key ranges at times).
basin=(run "$src/tests/data/mpi_basin.json" -q --no-plot --render none --checkpoint-every 0
       --checkpoint-seconds 0)
"$pbf" "${basin[@]}" --out "$work/basin1" > /dev/null
for n in 2 4; do
    "${mpi[@]}" -np $n "$pbf" "${basin[@]}" --out "$work/basin$n" > "$work/basin$n.log" 2>&1 ||
        { cat "$work/basin$n.log"; fail "sparse basin on $n ranks failed"; }
    frames=$(same_frames "$work/basin1" "$work/basin$n")
    echo "sparse basin, $n ranks: $frames frames bit-identical"
done

# A cube of water, 64 particles a side, filling a cubic tank, on 8 ranks
# (oversubscribed): the same frames as one process, and a halo of one
# kernel radius: the whole cube is inside one brick of the key, so the
# ranges are slabs of 4 cells, whose ghosts / owned is 2 / 4 (perfect
# octants would give 0.2; a halo of two cells, 1.0).
cube=(run "$src/tests/data/mpi_cube.json" -q --no-plot --render none --checkpoint-every 0
      --checkpoint-seconds 0)
"$pbf" "${cube[@]}" --out "$work/cube1" > /dev/null
"${mpi[@]}" -np 8 "$pbf" "${cube[@]}" --out "$work/cube8" > "$work/cube8.log" 2>&1 ||
    { cat "$work/cube8.log"; fail "cube on 8 ranks failed"; }
frames=$(same_frames "$work/cube1" "$work/cube8")
ratio=$(python3 - "$work/cube8/summary.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
ratios = [g / n for g, n in zip(s["rank_ghosts"], s["rank_particles"])]
assert len(ratios) == 8 and max(ratios) <= 0.5 + 1e-9, ratios
print(f"{max(ratios):.3f}")
PY
) || fail "cube on 8 ranks: more ghosts than a halo of one kernel radius"
echo "cube on 8 ranks: $frames frames bit-identical, largest ghosts / owned $ratio"

# 10 km from the origin (every rank measures from the same local frame):
# the dam break against a solid (no rigid bodies: their forces are summed
# per rank, so they agree only to rounding).
far=(run "$src/tests/data/mpi_far.json" -q --no-plot --render none --checkpoint-every 0
     --checkpoint-seconds 0)
"$pbf" "${far[@]}" --out "$work/far1" > /dev/null
"${mpi[@]}" -np 2 "$pbf" "${far[@]}" --out "$work/far2" > "$work/far2.log" 2>&1 ||
    { cat "$work/far2.log"; fail "scene 10 km away on 2 ranks failed"; }
frames=$(same_frames "$work/far1" "$work/far2")
echo "10 km from the origin, 2 ranks: $frames frames bit-identical"

# Driven solids (the shaken tank's walls): every rank places them the same way.
shaken=(run "$src/scenes/shaken_tank.json" -q --no-plot --render none --checkpoint-every 0
        --checkpoint-seconds 0 --frames 10)
"$pbf" "${shaken[@]}" --out "$work/shaken1" > /dev/null
"${mpi[@]}" -np 2 "$pbf" "${shaken[@]}" --out "$work/shaken2" > "$work/shaken2.log" 2>&1 ||
    { cat "$work/shaken2.log"; fail "shaken tank on 2 ranks failed"; }
frames=$(same_frames "$work/shaken1" "$work/shaken2")
echo "driven solids, 2 ranks: $frames frames bit-identical"

# An inlet and outlets (one in the middle of the block): each rank removes its
# own particles, and the rest keep the one-process order.
outflow=(run "$src/tests/data/outflow.json" -q --no-plot --render none --checkpoint-every 0
         --checkpoint-seconds 0)
"$pbf" "${outflow[@]}" --out "$work/outflow1" > /dev/null
"${mpi[@]}" -np 2 "$pbf" "${outflow[@]}" --out "$work/outflow2" > "$work/outflow2.log" 2>&1 ||
    { cat "$work/outflow2.log"; fail "inlet and outlets on 2 ranks failed"; }
frames=$(same_frames "$work/outflow1" "$work/outflow2")
removed=$(grep -o '"removed_particles": [0-9]*' "$work/outflow2/summary.json" | grep -o '[0-9]*$')
[ "${removed:-0}" -gt 100 ] || fail "outflow on 2 ranks removed ${removed:-no} particles"
cmp -s <(grep -o '"removed_particles": [0-9]*' "$work/outflow1/summary.json") \
    <(grep -o '"removed_particles": [0-9]*' "$work/outflow2/summary.json") ||
    fail "outflow: 2 ranks removed a different count from one process"
echo "inlet and outlets, 2 ranks: $frames frames bit-identical, $removed particles removed"

# Surface tension with adhesion on the walls and a solid: the cohesion's pass
# reads the ghosts' x* and densities (exchanged for the density constraint
# already); the curvature force exchanges the ghosts' g, band normals and
# kappa between its passes (computed by their owners: a ghost's own
# neighbourhood is incomplete).
tension=(run "$src/tests/data/mpi_surface_tension.json" -q --no-plot --render none
         --checkpoint-every 0 --checkpoint-seconds 0)
"$pbf" "${tension[@]}" --out "$work/tension1" > /dev/null
"${mpi[@]}" -np 2 "$pbf" "${tension[@]}" --out "$work/tension2" > "$work/tension2.log" 2>&1 ||
    { cat "$work/tension2.log"; fail "surface tension scene on 2 ranks failed"; }
frames=$(same_frames "$work/tension1" "$work/tension2")
echo "surface tension + adhesion, 2 ranks: $frames frames bit-identical"

# Checkpoints across rank counts.
"${mpi[@]}" -np 2 "$pbf" "${base[@]}" --frames 8 --out "$work/resume3" > "$work/ck.log" 2>&1 ||
    { cat "$work/ck.log"; fail "2-rank run to frame 8 failed"; }
cp -r "$work/resume3" "$work/resume1"
rm -f "$work"/resume{1,3}/frame_0001*.ply
"${mpi[@]}" -np 3 "$pbf" "${dam[@]}" --resume --out "$work/resume3" > "$work/r3.log" 2>&1 ||
    { cat "$work/r3.log"; fail "resume on 3 ranks failed"; }
"$pbf" "${dam[@]}" --resume --out "$work/resume1" > "$work/r1.log" 2>&1 ||
    { cat "$work/r1.log"; fail "resume in one process failed"; }
[ -e "$work/resume3/frame_00018.ply" ] || fail "the resumed run did not reach frame 18"
frames=$(same_frames "$work/dam1" "$work/resume3")
echo "2 ranks -> resume on 3: $frames frames bit-identical"
frames=$(same_frames "$work/dam1" "$work/resume1")
echo "2 ranks -> resume on 1: $frames frames bit-identical"
check_summary "$work/resume3" 3 || fail "summary.json after the resume on 3 ranks"
echo "PASS"
