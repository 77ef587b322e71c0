#!/usr/bin/env python3
"""Cost-error curve of the density solve (docs/performance.md, "Accuracy per cost").

Runs the dam break with fixed iteration counts and with error-controlled
iterations (solver.max_density_error), each with and without the options under
test, and reports for every run the cost (wall seconds per simulated second,
2 threads, no particle files written) against the time-averaged average and
maximum compression (the per-frame columns avg_density_error and
max_density_error of stats.csv, averaged over the frames).

    scripts/accuracy_curve.py [--pbf build/release/pbf] [--sizes 17k,140k]
                              [--frames 120] [--out out/accuracy]

Writes OUT/curve.csv, OUT/curve.md (a Markdown table) and OUT/curve.png
(matplotlib, from Debian's python3-matplotlib; skipped with a message when it
is missing).
"""

import argparse
import csv
import json
import os
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent

# particle radius of each size of the dam break (scenes/dam_break.json: 0.01 m gives 17,500)
SIZES = {"17k": 0.01, "140k": 0.005}

FIXED = [2, 4, 8, 16]
TOLERANCES = [0.001, 0.0005, 0.0002, 0.0001]


def modes(methods):
    """(label, method, overrides) for every point of the curve."""
    for method, extra in methods:
        for n in FIXED:
            yield f"{n} it", method, extra + [f"solver.iterations={n}"]
        for tol in TOLERANCES:
            yield f"tol {100 * tol:g} %", method, extra + [
                f"solver.max_density_error={tol}",
                "solver.min_iterations=1",
                "solver.max_iterations=100",
            ]


def run_one(pbf, radius, frames, overrides, out):
    args = [pbf, "run", str(ROOT / "scenes" / "dam_break.json"), "-q", "--no-particles",
            "--threads", "2", "--frames", str(frames), "--out", str(out),
            "--set", f"particle_radius={radius}", "--set", "output.checkpoints=false"]
    for o in overrides:
        args += ["--set", o]
    env = dict(os.environ, OMP_WAIT_POLICY="passive")
    subprocess.run(args, check=True, env=env, stdout=subprocess.DEVNULL)
    summary = json.loads((out / "summary.json").read_text())
    with open(out / "stats.csv") as f:
        rows = list(csv.DictReader(f))[1:]  # frame 0 is the initial state
    mean = lambda key: sum(float(r[key]) for r in rows) / len(rows)
    return {
        "wall_per_sim_s": summary["wall_seconds"] / summary["simulated_seconds"],
        "avg_compression": mean("avg_density_error"),
        "max_compression": mean("max_density_error"),
        "iterations": mean("iterations"),
        "substeps": sum(int(r["substeps"]) for r in rows),
        "particles": summary["particles"],
    }


def plot(points, path):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("accuracy_curve: matplotlib missing (apt-get install python3-matplotlib): no plot")
        return
    sizes = sorted({p["size"] for p in points}, key=lambda s: SIZES[s], reverse=True)
    fig, axes = plt.subplots(len(sizes), 2, figsize=(11, 4.2 * len(sizes)), squeeze=False)
    for row, size in enumerate(sizes):
        for col, key in enumerate(["avg_compression", "max_compression"]):
            ax = axes[row][col]
            for method in sorted({p["method"] for p in points}):
                for kind, marker in (("it", "o-"), ("tol", "s--")):
                    sel = [p for p in points if p["size"] == size and p["method"] == method
                           and p["mode"].startswith(kind)]
                    if not sel:
                        continue
                    sel.sort(key=lambda p: p["wall_per_sim_s"])
                    ax.plot([p["wall_per_sim_s"] for p in sel], [100 * p[key] for p in sel],
                            marker, label=f"{method}, {'fixed iterations' if kind == 'it' else 'tolerance'}")
                    for p in sel:
                        ax.annotate(p["mode"], (p["wall_per_sim_s"], 100 * p[key]),
                                    fontsize=7, xytext=(3, 3), textcoords="offset points")
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_xlabel("wall seconds per simulated second (2 threads)")
            ax.set_ylabel(("average" if col == 0 else "maximum") + " compression, time-averaged (%)")
            ax.set_title(f"dam break {size}")
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    print(f"accuracy_curve: {path}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--pbf", default=str(ROOT / "build" / "release" / "pbf"))
    parser.add_argument("--sizes", default="17k,140k")
    parser.add_argument("--frames", type=int, default=120)
    parser.add_argument("--out", default="out/accuracy")
    parser.add_argument("--method", action="append", default=[],
                        help="NAME:FIELD=VALUE[,FIELD=VALUE] compared with plain Jacobi, "
                             "e.g. omega1.5:solver.over_relaxation=1.5")
    args = parser.parse_args()
    methods = [("jacobi", [])]
    for m in args.method:
        name, _, sets = m.partition(":")
        methods.append((name, [s for s in sets.split(",") if s]))
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    points = []
    for size in args.sizes.split(","):
        for label, method, overrides in modes(methods):
            result = run_one(args.pbf, SIZES[size], args.frames, overrides, out / "run")
            result.update(size=size, method=method, mode=label)
            points.append(result)
            print(f"{size:>5} {method:>10} {label:>12}: {result['wall_per_sim_s']:7.2f} s/s, "
                  f"avg {100 * result['avg_compression']:.4f} %, "
                  f"max {100 * result['max_compression']:.3f} %, "
                  f"{result['iterations']:.2f} iterations", flush=True)
    keys = ["size", "method", "mode", "particles", "wall_per_sim_s", "avg_compression",
            "max_compression", "iterations", "substeps"]
    with open(out / "curve.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        for p in points:
            w.writerow({k: p[k] for k in keys})
    with open(out / "curve.md", "w") as f:
        f.write("| size | method | mode | wall s / sim s | avg compression | max compression "
                "| iterations / substep |\n| --- | --- | --- | --- | --- | --- | --- |\n")
        for p in points:
            f.write(f"| {p['size']} | {p['method']} | {p['mode']} | {p['wall_per_sim_s']:.2f} | "
                    f"{100 * p['avg_compression']:.4f} % | {100 * p['max_compression']:.3f} % | "
                    f"{p['iterations']:.2f} |\n")
    plot(points, out / "curve.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
