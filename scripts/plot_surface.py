#!/usr/bin/env python3
"""Plots a water surface mesh (OBJ written by `pbf mesh`) as a shaded PNG.

Usage: scripts/plot_surface.py SURFACE.obj OUT.png [--domain X0 Y0 Z0 X1 Y1 Z1] [--title TEXT]

Needs python3-matplotlib and python3-numpy (Debian packages). The scene's y
axis is up; the tank (domain box) is drawn as a wire frame. Each triangle is
shaded with a headlight-free Lambert + ambient term so the shape reads without
a renderer; this is a plot for documentation, not a render.
"""
import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection  # noqa: E402


def load_obj(path):
    vertices, faces = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                vertices.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("f "):
                faces.append([int(x.split("/")[0]) - 1 for x in line.split()[1:4]])
    if not faces:
        raise SystemExit(f"{path}: no triangles")
    return np.array(vertices), np.array(faces)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("obj")
    parser.add_argument("png")
    parser.add_argument("--domain", type=float, nargs=6, default=None)
    parser.add_argument("--title", default="")
    parser.add_argument("--elev", type=float, default=22.0)
    parser.add_argument("--azim", type=float, default=-58.0)
    args = parser.parse_args()

    v, f = load_obj(args.obj)
    v = v[:, [0, 2, 1]]  # scene y-up -> matplotlib z-up
    tri = v[f]
    normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-12)
    # The axis swap mirrors the scene, so the outward normal flips sign.
    normals = -normals
    light = np.array([-0.4, -0.6, 0.7])
    light /= np.linalg.norm(light)
    lambert = np.clip(normals @ light, 0.0, 1.0)
    up = np.clip(normals[:, 2], 0.0, 1.0)
    deep, shallow = np.array([0.05, 0.25, 0.55]), np.array([0.55, 0.80, 0.95])
    colour = deep + (shallow - deep) * (0.25 + 0.75 * lambert[:, None])
    colour = np.clip(colour + 0.12 * up[:, None] ** 8, 0.0, 1.0)  # sky glint on flat water

    fig = plt.figure(figsize=(10, 6), dpi=120)
    ax = fig.add_subplot(projection="3d")
    ax.add_collection3d(Poly3DCollection(tri, facecolors=colour, edgecolors="none", linewidths=0))
    if args.domain:
        x0, y0, z0, x1, y1, z1 = args.domain
        lo, hi = np.array([x0, z0, y0]), np.array([x1, z1, y1])
    else:
        lo, hi = v.min(axis=0), v.max(axis=0)
    corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
    edges = [(a, b) for a in range(8) for b in range(a + 1, 8) if bin(a ^ b).count("1") == 1]
    ax.add_collection3d(Line3DCollection([(corners[a], corners[b]) for a, b in edges], colors="0.35", linewidths=0.8))
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    ax.set_box_aspect(hi - lo)
    ax.view_init(elev=args.elev, azim=args.azim)
    ax.set_axis_off()
    if args.title:
        ax.set_title(args.title)
    fig.tight_layout()
    fig.savefig(args.png, bbox_inches="tight")
    print(f"{args.png}: {len(f)} triangles")


if __name__ == "__main__":
    main()
