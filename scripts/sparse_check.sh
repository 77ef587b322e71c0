#!/usr/bin/env bash
# Memory that follows the water: the 60 m x 4 m x 60 m basin (two 30 cm
# blocks in opposite corners, r = 5 mm, 54,000 particles) and the 1 km x 20 m
# x 1 km ocean (one 1 m block at a far corner, r = 2 cm, 15,625 particles)
# of bench/scenes/, each against the same water in a tight domain, run to
# frame 10 on every backend. Prints each run's peak resident memory
# (/usr/bin/time) and wall time, and the difference in position (median,
# 99th percentile, largest, centre of mass) between the huge and the tight
# domain at the last frame (the basin's far block compared after moving it
# by the domains' offset, 56 m).
# Usage: scripts/sparse_check.sh [PBF] [OUT]   (default build/release/pbf, build/release/sparse_check)
set -euo pipefail
cd "$(dirname "$0")/.."
pbf=${1:-build/release/pbf}
out=${2:-build/release/sparse_check}
frames=${FRAMES:-10}
mkdir -p "$out"
export OMP_WAIT_POLICY=passive
run() {  # NAME SCENE LAUNCHER... -- ARGS...
    local name=$1 scene=$2
    shift 2
    local launch=()
    while [ "$1" != "--" ]; do launch+=("$1"); shift; done
    shift
    /usr/bin/time -f "%M %e" -o "$out/$name.time" "${launch[@]}" "$pbf" run "$scene" -q --no-plot \
        --render none --checkpoint-every 0 --checkpoint-seconds 0 --frames "$frames" \
        --out "$out/$name" "$@" > "$out/$name.log" 2>&1 || { cat "$out/$name.log"; exit 1; }
    read -r kb seconds < "$out/$name.time"
    printf "%-28s peak %7.1f MB  %7.1f s\n" "$name" "$(echo "$kb / 1024" | bc -l)" "$seconds"
}
compare() {  # HUGE TIGHT SHIFT
    python3 - "$out/$1/frame_$(printf %05d "$frames").ply" "$out/$2/frame_$(printf %05d "$frames").ply" "$3" <<'PY'
import struct, sys
def read(path):
    data = open(path, "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    n = int([l for l in data[:end].split(b"\n") if l.startswith(b"element vertex")][0].split()[2])
    out = {}
    for k in range(n):
        x, y, z, vx, vy, vz, rho, i = struct.unpack_from("<7fI", data, end + 32 * k)
        out[i] = (x, y, z)
    return out
a, b, shift = read(sys.argv[1]), read(sys.argv[2]), float(sys.argv[3])
diffs, centre = [], [0.0, 0.0, 0.0]
for i, p in a.items():
    q = b[i]
    s = shift if p[0] > 30 and shift else 0.0
    d = (p[0] - s - q[0], p[1] - q[1], p[2] - s - q[2])
    diffs.append(max(abs(c) for c in d))
    centre = [c + e / len(a) for c, e in zip(centre, d)]
diffs.sort()
print(f"    {len(a)} particles, position difference: median {diffs[len(diffs) // 2]:.2e} m, "
      f"99th percentile {diffs[int(0.99 * (len(diffs) - 1))]:.2e} m, largest {diffs[-1]:.2e} m; "
      f"centres of mass {max(abs(c) for c in centre):.2e} m apart")
PY
}
mpi=(mpirun --oversubscribe --allow-run-as-root --mca btl self,vader -np 2 env OMP_NUM_THREADS=1)
for scene in basin ocean; do
    for device in cpu reference cuda-on-cpu; do
        run "${scene}_sparse_$device" "bench/scenes/sparse_$scene.json" -- --device "$device"
        run "${scene}_tight_$device" "bench/scenes/tight_$scene.json" -- --device "$device"
        compare "${scene}_sparse_$device" "${scene}_tight_$device" "$([ $scene = basin ] && echo 56 || echo 0)"
    done
    if command -v mpirun > /dev/null; then
        run "${scene}_sparse_2ranks" "bench/scenes/sparse_$scene.json" "${mpi[@]}" -- --threads 1
        run "${scene}_tight_2ranks" "bench/scenes/tight_$scene.json" "${mpi[@]}" -- --threads 1
        compare "${scene}_sparse_2ranks" "${scene}_tight_2ranks" "$([ $scene = basin ] && echo 56 || echo 0)"
        cmp -s "$out/${scene}_sparse_2ranks/frame_$(printf %05d "$frames").ply" \
            "$out/${scene}_sparse_cpu/frame_$(printf %05d "$frames").ply" &&
            echo "    2 ranks: the last frame byte-identical to one process"
    fi
done
