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
import resource
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent

# particle radius of each size of the dam break (scenes/dam_break.json: 0.01 m gives 17,500)
SIZES = {"17k": 0.01, "140k": 0.005}

FIXED = [2, 4, 8, 16]
TOLERANCES = [0.001, 0.0005, 0.0002, 0.0001]


def modes(methods, fixed, tolerances):
    """(label, method, overrides) for every point of the curve."""
    for method, extra in methods:
        for n in fixed:
            yield f"{n} it", method, extra + [f"solver.iterations={n}"]
        for tol in tolerances:
            # the method's own settings last: they may set min_iterations
            yield f"tol {100 * tol:g} %", method, [
                f"solver.max_density_error={tol}",
                "solver.min_iterations=1",
                "solver.max_iterations=100",
            ] + extra


def run_one(pbf, radius, frames, overrides, out):
    args = [pbf, "run", str(ROOT / "scenes" / "dam_break.json"), "-q", "--no-particles",
            "--threads", "2", "--frames", str(frames), "--out", str(out),
            "--set", f"particle_radius={radius}", "--set", "output.checkpoints=false"]
    for o in overrides:
        args += ["--set", o]
    env = dict(os.environ, OMP_WAIT_POLICY="passive")
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(args, check=True, env=env, stdout=subprocess.DEVNULL)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    summary = json.loads((out / "summary.json").read_text())
    with open(out / "stats.csv") as f:
        rows = list(csv.DictReader(f))[1:]  # frame 0 is the initial state
    mean = lambda key: sum(float(r[key]) for r in rows) / len(rows)
    return {
        "wall_per_sim_s": summary["wall_seconds"] / summary["simulated_seconds"],
        # CPU time of both threads: on a shared machine (the 2-core development
        # machine with other builds) wall time measures the neighbours' load.
        "cpu_per_sim_s": cpu / summary["simulated_seconds"],
        "avg_compression": mean("avg_density_error"),
        "max_compression": mean("max_density_error"),
        "iterations": mean("iterations"),
        "substeps": sum(int(r["substeps"]) for r in rows),
        "particles": summary["particles"],
    }


def plot(points, out):
    """The curve through the project's one plotting path: a figure description
    (OUT/curve.plot.json) drawn by scripts/pbf_plot.py, as pbf plot and pbf
    validate draw theirs."""
    sizes = sorted({p["size"] for p in points}, key=lambda s: SIZES[s], reverse=True)
    panels = []
    for size in sizes:
        for key, name in (("avg_compression", "average"), ("max_compression", "maximum")):
            series = []
            for method in dict.fromkeys(p["method"] for p in points):
                for kind, style, what in (("fixed", "line", "fixed iterations"),
                                          ("tol", "dashed", "tolerance")):
                    sel = sorted((p for p in points if p["size"] == size and
                                  p["method"] == method and
                                  p["mode"].startswith("tol") == (kind == "tol")),
                                 key=lambda p: p["cpu_per_sim_s"])
                    if sel:
                        series.append({"label": f"{method}, {what}", "style": style,
                                       "x": [p["cpu_per_sim_s"] for p in sel],
                                       "y": [100 * p[key] for p in sel]})
            panels.append({"title": f"dam break {size}: {name} compression",
                           "x_label": "CPU seconds per simulated second (2 threads)",
                           "y_label": f"{name} compression, time-averaged (%)",
                           "log_y": True, "series": series})
    data = out / "curve.plot.json"
    data.write_text(json.dumps({"title": "Accuracy per cost: PBF density solve",
                                "columns": 2, "panels": panels}))
    status = subprocess.run(["/usr/bin/python3", str(ROOT / "scripts" / "pbf_plot.py"),
                             str(data), str(out / "curve.png")]).returncode
    if status == 3:
        print("accuracy_curve: no plot: apt-get install python3-matplotlib")
    elif status == 0:
        print(f"accuracy_curve: {out / 'curve.png'}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--pbf", default=str(ROOT / "build" / "release" / "pbf"))
    parser.add_argument("--sizes", default="17k,140k")
    parser.add_argument("--frames", type=int, default=120)
    parser.add_argument("--out", default="out/accuracy")
    parser.add_argument("--fixed", default=",".join(map(str, FIXED)),
                        help="fixed iteration counts, e.g. 4,8")
    parser.add_argument("--tolerances", default=",".join(map(str, TOLERANCES)),
                        help="solver.max_density_error values, e.g. 0.0005,0.0002")
    parser.add_argument("--method", action="append", default=[],
                        help="NAME:FIELD=VALUE[,FIELD=VALUE] compared with plain Jacobi, "
                             "e.g. omega1.5:solver.over_relaxation=1.5")
    parser.add_argument("--replot", action="store_true",
                        help="only draw OUT/curve.png again from OUT/curve.csv")
    args = parser.parse_args()
    if args.replot:
        with open(pathlib.Path(args.out) / "curve.csv") as f:
            points = [{k: (v if k in ("size", "method", "mode") else float(v))
                       for k, v in row.items()} for row in csv.DictReader(f)]
        plot(points, pathlib.Path(args.out))
        return 0
    # plain Jacobi explicitly: a tolerance alone selects over-relaxation
    # (its automatic default)
    methods = [("jacobi", ["solver.over_relaxation=1"])]
    for m in args.method:
        name, _, sets = m.partition(":")
        methods.append((name, [s for s in sets.split(",") if s]))
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    points = []
    for size in args.sizes.split(","):
        for label, method, overrides in modes(methods, [int(n) for n in args.fixed.split(",") if n],
                                           [float(t) for t in args.tolerances.split(",") if t]):
            result = run_one(args.pbf, SIZES[size], args.frames, overrides, out / "run")
            result.update(size=size, method=method, mode=label)
            points.append(result)
            print(f"{size:>5} {method:>10} {label:>12}: {result['wall_per_sim_s']:7.2f} s/s, "
                  f"CPU {result['cpu_per_sim_s']:7.2f} s/s, "
                  f"avg {100 * result['avg_compression']:.4f} %, "
                  f"max {100 * result['max_compression']:.3f} %, "
                  f"{result['iterations']:.2f} iterations", flush=True)
    keys = ["size", "method", "mode", "particles", "wall_per_sim_s", "cpu_per_sim_s", "avg_compression",
            "max_compression", "iterations", "substeps"]
    with open(out / "curve.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        for p in points:
            w.writerow({k: p[k] for k in keys})
    with open(out / "curve.md", "w") as f:
        f.write("| size | method | mode | wall s / sim s | CPU s / sim s | avg compression "
                "| max compression | iterations / substep |\n"
                "| --- | --- | --- | --- | --- | --- | --- | --- |\n")
        for p in points:
            f.write(f"| {p['size']} | {p['method']} | {p['mode']} | {p['wall_per_sim_s']:.2f} | "
                    f"{p['cpu_per_sim_s']:.2f} | "
                    f"{100 * p['avg_compression']:.4f} % | {100 * p['max_compression']:.3f} % | "
                    f"{p['iterations']:.2f} |\n")
    plot(points, out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
