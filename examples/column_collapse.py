#!/usr/bin/env python3
"""Collapse of a water column (Martin & Moyce 1952), built in code with pbf.

A column of width a and height 2a stands against the left wall of a tank
and collapses when released. Martin & Moyce measured the surge front x_max
along the floor and the height h of the residual column at the wall in the
dimensionless forms

    Z = x_max / a     against   T = t sqrt(2 g / a)
    H = h / (2 a)     against   T

This script steps the simulation frame by frame, measures both on the
particle positions (numpy views of the World) and prints them, with the
front that Ritter's shallow-water solution for an ideal dam break gives,
x = a + 2 t sqrt(g 2a), i.e. Z = 1 + 2T (an upper bound: the real front is slowed by the
wall, the floor and the curved surface). With matplotlib installed it also
plots them (--plot FILE).

    PYTHONPATH=build/release/python python3 examples/column_collapse.py
    python3 examples/column_collapse.py --radius 0.00125 --plot collapse.png   # finer
"""

import argparse
import math
import time

import numpy as np

import pbf


def column_definition(a, radius, tank_length, depth):
    d = pbf.WorldDef(name="column_collapse")
    d.simulation.domain = ((0, 0, 0), (tank_length, 2.5 * a, depth))
    d.simulation.particle_radius = radius
    d.fluid_blocks.append(pbf.FluidBlock((0, 0, 0), (a, 2 * a, depth)))
    d.fps = 200  # frames of 5 ms: the front moves ~1 cm per frame
    return d


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--width", type=float, default=0.1, help="column width a, m")
    parser.add_argument("--radius", type=float, default=0.0025, help="particle radius, m")
    parser.add_argument("--until", type=float, default=3.5, help="last T = t sqrt(2g/a)")
    parser.add_argument("--plot", help="write a plot of Z(T) and H(T) to this file")
    args = parser.parse_args()

    a = args.width
    g = 9.81
    world = pbf.World(column_definition(a, args.radius, tank_length=5 * a, depth=0.04))
    spacing = 2 * args.radius
    time_scale = math.sqrt(2 * g / a)  # T = t * time_scale
    print(f"column {a:.3f} m x {2 * a:.3f} m, {world.particle_count} particles, "
          f"{pbf.threads()} threads")
    print(f"{'T':>6} {'Z=x/a':>7} {'Ritter':>7} {'H=h/2a':>7} {'err %':>6} {'ms':>6}")

    rows = []
    started = time.perf_counter()
    while world.time * time_scale < args.until:
        report = world.step_frame()
        x = world.positions  # (N, 3) view, no copy
        on_floor = x[:, 1] < 1.5 * spacing
        at_wall = x[:, 0] < 1.5 * spacing
        front = x[on_floor, 0].max() if on_floor.any() else 0.0
        height = x[at_wall, 1].max() + args.radius if at_wall.any() else 0.0
        T = report.time * time_scale
        Z = (front + args.radius) / a
        ritter = (a + 2 * report.time * math.sqrt(g * 2 * a)) / a
        H = height / (2 * a)
        rows.append((T, Z, H))
        print(f"{T:6.3f} {Z:7.3f} {ritter:7.3f} {H:7.3f} "
              f"{100 * report.statistics.average_density_error:6.2f} "
              f"{report.step_ms * report.substeps:6.1f}")
    print(f"{world.frame} frames in {time.perf_counter() - started:.1f} s wall")

    if args.plot:
        try:
            import matplotlib

            matplotlib.use("Agg")
            import matplotlib.pyplot as plt
        except ImportError:
            print("matplotlib is not installed (apt-get install python3-matplotlib): no plot")
            return
        T, Z, H = np.array(rows).T
        fig, ax = plt.subplots(figsize=(6, 4))
        ax.plot(T, Z, label="surge front Z = x/a (pbf)")
        ax.plot(T, 1 + 2 * T, "--", label="Ritter, ideal dam break: Z = 1 + 2T")
        ax.plot(T, H, label="column height H = h/2a (pbf)")
        ax.set_xlabel("T = t sqrt(2g/a)")
        ax.legend()
        ax.grid(alpha=0.3)
        fig.tight_layout()
        fig.savefig(args.plot, dpi=120)
        print(f"plot written to {args.plot}")


if __name__ == "__main__":
    main()
