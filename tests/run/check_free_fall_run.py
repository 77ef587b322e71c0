"""`pbf run` end to end on the falling cube (cli.run_small).

Runs `pbf run scenes/cube_drop.json --frames 3` and checks what the command
line promises and what the physics says, so that a broken run fails here:
- the exit status is 0 and the last line names the frames, particles and
  output directory;
- stats.csv has frames 0..3 and the kinetic energy of frame 3 is that of a
  free fall, 1/2 M (g t)^2 with M = particles * rho0 * (2 r)^3 (the cube is
  still in the air at t = 0.1 s): within 3 % (the solver's internal motion
  and the semi-implicit step take under 1 %); wrong gravity, mass, time step
  or frame length fail it;
- summary.json agrees with stats.csv (frames, particles, substeps).
Usage: check_free_fall_run.py PBF SCENE OUT_DIR
"""
import csv
import json
import pathlib
import subprocess
import sys

pbf, scene, out = sys.argv[1], sys.argv[2], pathlib.Path(sys.argv[3])
run = subprocess.run([pbf, "run", scene, "--frames", "3", "-q", "--no-plot", "--out", str(out)],
                     capture_output=True, text=True)
print(run.stdout + run.stderr)
assert run.returncode == 0, f"exit status {run.returncode}"
assert f"3 frames, 3375 particles" in run.stdout and str(out) in run.stdout, "summary line"

rows = list(csv.DictReader(open(out / "stats.csv")))
assert [int(r["frame"]) for r in rows] == [0, 1, 2, 3], "frames 0..3"
summary = json.load(open(out / "summary.json"))
radius, rho0, g, t = summary["particle_radius"], 1000.0, 9.81, float(rows[-1]["time"])
mass = summary["particles"] * rho0 * (2 * radius) ** 3
expected = 0.5 * mass * (g * t) ** 2
energy = float(rows[-1]["kinetic_energy"])
print(f"kinetic energy at t = {t} s: {energy:.4f} J, free fall {expected:.4f} J")
assert abs(energy - expected) <= 0.03 * expected, "not a free fall"
assert summary["frames"] == 3 and summary["particles"] == 3375
assert summary["substeps"] == sum(int(r["substeps"]) for r in rows)
print("ok")
