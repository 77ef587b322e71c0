"""ParaView opens a pbf run as a user would (run with pvpython; CTest test
clients.paraview): particles.pvd has one time step per frame at k / fps, the
particle count of each frame, and the point arrays velocity, density and id
equal to the PLY frame's; surface/surface.pvd likewise for the meshes, with
normals. Usage: pvpython paraview_test.py RUN_DIR
"""

import json
import os
import sys

import numpy as np
from paraview import servermanager
from paraview.simple import PVDReader, XMLUnstructuredGridReader
from vtkmodules.util.numpy_support import vtk_to_numpy

run = sys.argv[1]
failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAIL:", message)


def read_ply(path):
    """pbf's PLY files, parsed independently of pbf: header, then records."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode().splitlines()
    counts = {l.split()[1]: int(l.split()[2]) for l in header if l.startswith("element")}
    props, element = [], None
    for l in header:
        if l.startswith("element"):
            element = l.split()[1]
        elif l.startswith("property") and element == "vertex":
            props.append((l.split()[2], "<u4" if l.split()[1] == "uint" else "<f4"))
    return np.frombuffer(data, dtype=np.dtype(props), count=counts["vertex"], offset=end), counts


fps = json.load(open(os.path.join(run, "summary.json")))["fps"]
frames = sorted(int(n[6:11]) for n in os.listdir(run) if n.startswith("frame_") and n.endswith(".ply"))

particles = PVDReader(FileName=os.path.join(run, "particles.pvd"))
times = list(particles.TimestepValues)
check(len(times) == len(frames), f"particles.pvd: {len(times)} time steps for {len(frames)} frames")
for k, t in zip(frames, times):
    check(abs(t - k / fps) <= 1e-12 * max(1.0, t), f"frame {k}: time {t!r}, expected {k / fps!r}")
for k, t in zip(frames, times):
    particles.UpdatePipeline(t)
    grid = servermanager.Fetch(particles)
    ply, _ = read_ply(os.path.join(run, f"frame_{k:05d}.ply"))
    n = grid.GetNumberOfPoints()
    check(n == len(ply), f"frame {k}: {n} points in ParaView, {len(ply)} in the PLY")
    check(grid.GetNumberOfCells() == n and grid.GetCellType(0) == 1,  # VTK_VERTEX
          f"frame {k}: not one vertex cell per particle")
    data = grid.GetPointData()
    arrays = {data.GetArrayName(i): vtk_to_numpy(data.GetArray(i)) for i in range(data.GetNumberOfArrays())}
    check(set(arrays) == {"velocity", "density", "id"}, f"frame {k}: point arrays {sorted(arrays)}")
    if n != len(ply) or set(arrays) != {"velocity", "density", "id"}:
        continue
    xyz = vtk_to_numpy(grid.GetPoints().GetData())
    check(np.array_equal(xyz, np.stack([ply["x"], ply["y"], ply["z"]], axis=1)), f"frame {k}: positions differ")
    check(np.array_equal(arrays["velocity"], np.stack([ply["vx"], ply["vy"], ply["vz"]], axis=1)),
          f"frame {k}: velocity differs")
    check(np.array_equal(arrays["density"], ply["density"]), f"frame {k}: density differs")
    check(np.array_equal(arrays["id"], ply["id"]), f"frame {k}: id differs")
print(f"particles.pvd: {len(times)} time steps, {frames[-1] + 1} frames checked against the PLY files")

# Opened as a numbered series without the .pvd, the files' TimeValue gives the same times.
series = XMLUnstructuredGridReader(FileName=[os.path.join(run, f"frame_{k:05d}.vtu") for k in frames])
check(list(series.TimestepValues) == [k / fps for k in frames],
      f"frame_*.vtu as a series: times {list(series.TimestepValues)}")

surface_dir = os.path.join(run, "surface")
surfaces = sorted(int(n[8:13]) for n in os.listdir(surface_dir) if n.startswith("surface_") and n.endswith(".vtp"))
check(len(surfaces) == len(frames), f"{len(surfaces)} surface .vtp files for {len(frames)} frames")
meshes = PVDReader(FileName=os.path.join(surface_dir, "surface.pvd"))
times = list(meshes.TimestepValues)
check(times == [k / fps for k in surfaces], f"surface.pvd: times {times}")
for k, t in zip(surfaces, times):
    meshes.UpdatePipeline(t)
    poly = servermanager.Fetch(meshes)
    _, counts = read_ply(os.path.join(surface_dir, f"surface_{k:05d}.ply"))
    check(poly.GetNumberOfPoints() == counts["vertex"] and poly.GetNumberOfPolys() == counts["face"],
          f"surface {k}: {poly.GetNumberOfPoints()} points / {poly.GetNumberOfPolys()} triangles, "
          f"PLY {counts['vertex']} / {counts['face']}")
    normals = poly.GetPointData().GetNormals()
    check(normals is not None and normals.GetNumberOfTuples() == poly.GetNumberOfPoints(),
          f"surface {k}: no normals")
    if normals is not None:
        length = np.linalg.norm(vtk_to_numpy(normals), axis=1)
        check(np.allclose(length, 1.0, atol=1e-5), f"surface {k}: normals are not unit vectors")
print(f"surface.pvd: {len(times)} time steps checked against the PLY meshes")

if failures:
    print(f"{len(failures)} checks failed")
    sys.exit(1)
print("paraview: all checks passed")
