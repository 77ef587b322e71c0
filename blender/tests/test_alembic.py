"""The documented one-line Alembic conversion (blender/pbf_to_alembic.py),
then its file read back by Blender (CTest test clients.alembic):

    blender -b --factory-startup --python-exit-code 1 --python test_alembic.py -- RUN_DIR OUT.abc

At every frame k the particle mesh has frame k's point count at frame k's
positions (Y-up in the file: Alembic's convention, which Maya shares) and the
surface mesh has surface k's vertex count. Exits 77 (skipped) in a Blender
built without Alembic, as Debian's is.
"""

import os
import subprocess
import sys

import bpy
import numpy as np

argv = sys.argv[sys.argv.index("--") + 1:]
RUN, ABC = os.path.abspath(argv[0]), os.path.abspath(argv[1])
failures = []

if not bpy.app.build_options.alembic:
    print(f"SKIP: this Blender ({bpy.app.version_string}, {bpy.app.binary_path}) was built without "
          "Alembic (Debian's blender package is): the conversion cannot be tested here")
    sys.exit(77)

script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "pbf_to_alembic.py")
if os.path.exists(ABC):
    os.remove(ABC)
convert = subprocess.run([bpy.app.binary_path, "-b", "--factory-startup", "--python", script,
                          "--", RUN, ABC], capture_output=True, text=True)
print(convert.stdout[-2000:], convert.stderr[-2000:])
if convert.returncode != 0 or not os.path.isfile(ABC):
    print(f"FAIL: the conversion exited with {convert.returncode} and wrote no {ABC}")
    sys.exit(1)


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAIL:", message)


def vertex_count_and_xyz(path):
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode().splitlines()
    n = int(next(l for l in header if l.startswith("element vertex")).split()[2])
    props = []
    for l in header:
        if l.startswith("element face"):
            break
        if l.startswith("property"):
            props.append((l.split()[2], "<u4" if l.split()[1] == "uint" else "<f4"))
    v = np.frombuffer(data, dtype=np.dtype(props), count=n, offset=end)
    return n, np.stack([v["x"], v["y"], v["z"]], axis=1)


bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.wm.alembic_import(filepath=ABC, as_background_job=False)
scene = bpy.context.scene
name = "pbf " + os.path.basename(RUN)
objects = {o.name: o for o in scene.objects}
print("objects in the Alembic file:", sorted(objects))
particles = next((o for n, o in objects.items() if n.startswith(name + " particles")), None)
surface = next((o for n, o in objects.items() if n.startswith(name + " surface")), None)
check(particles is not None and surface is not None, "particles or surface missing from the file")
frames = sorted(int(n[6:11]) for n in os.listdir(RUN) if n.startswith("frame_") and n.endswith(".ply"))
if particles is not None and surface is not None:
    for k in frames:
        scene.frame_set(k)
        depsgraph = bpy.context.evaluated_depsgraph_get()
        mesh = particles.evaluated_get(depsgraph).to_mesh()
        n, xyz = vertex_count_and_xyz(os.path.join(RUN, f"frame_{k:05d}.ply"))
        check(len(mesh.vertices) == n, f"frame {k}: {len(mesh.vertices)} particles, PLY has {n}")
        if len(mesh.vertices) == n:
            co = np.zeros(3 * n, dtype=np.float32)
            mesh.vertices.foreach_get("co", co)
            world = np.array(particles.matrix_world.to_3x3()) @ co.reshape(-1, 3).T
            # Imported back into Blender (Z-up): (x, -z, y) of the file's Y-up positions.
            expected = np.stack([xyz[:, 0], -xyz[:, 2], xyz[:, 1]])
            check(np.abs(world - expected).max() < 1e-5, f"frame {k}: particle positions differ")
        m = surface.evaluated_get(depsgraph).to_mesh()
        vertices, _ = vertex_count_and_xyz(os.path.join(RUN, "surface", f"surface_{k:05d}.ply"))
        check(len(m.vertices) == vertices, f"frame {k}: surface has {len(m.vertices)} vertices, PLY {vertices}")
if failures:
    print(f"alembic: {len(failures)} checks failed")
    sys.exit(1)
print(f"alembic: all checks passed ({len(frames)} frames)")
