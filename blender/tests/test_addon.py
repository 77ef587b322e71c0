"""The add-on in Blender, headless (CTest test clients.blender):

    blender -b --factory-startup --python-exit-code 1 --python test_addon.py -- RUN_DIR WORK_DIR

RUN_DIR is the output of `pbf run --mesh` (particles, surface meshes, level
sets). The add-on is installed from a zip of blender/io_scene_pbf the way a
user installs it (BLENDER_USER_SCRIPTS should point into WORK_DIR), then:
at scene frame f the particle object holds run frame k = floor(t * fps_run)
(t the scene time) with that frame's point count and attribute values, the
surface object switches meshes with the frame, the level set is a Volume
whose surface has vertices, bodies.csv poses are keyframed, and positions
are turned from Y-up to Z-up.
"""

import json
import math
import os
import sys
import zipfile

import bpy
import numpy as np

argv = sys.argv[sys.argv.index("--") + 1:]
RUN, WORK = os.path.abspath(argv[0]), os.path.abspath(argv[1])
ADDON = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "io_scene_pbf")
failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAIL:", message)


def read_ply(path):
    """pbf's PLY files, parsed independently of the add-on."""
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


def attribute(mesh, name, field, width):
    a = mesh.attributes[name]
    out = np.zeros(len(a.data) * width, dtype=np.int32 if a.data_type == "INT" else np.float32)
    a.data.foreach_get(field, out)
    return out.reshape(-1, width) if width > 1 else out


# Install the add-on from a zip, as File > Preferences > Add-ons > Install does.
os.makedirs(WORK, exist_ok=True)
archive = os.path.join(WORK, "io_scene_pbf.zip")
with zipfile.ZipFile(archive, "w") as z:
    for name in sorted(os.listdir(ADDON)):
        if name.endswith(".py"):
            z.write(os.path.join(ADDON, name), os.path.join("io_scene_pbf", name))
bpy.ops.preferences.addon_install(filepath=archive, overwrite=True)
bpy.ops.preferences.addon_enable(module="io_scene_pbf")
check(hasattr(bpy.types, "IMPORT_SCENE_OT_pbf"), "the add-on did not register its operator")

for obj in list(bpy.data.objects):
    bpy.data.objects.remove(obj)
scene = bpy.context.scene
scene.render.fps, scene.render.fps_base = 24, 1.0  # the run has 30 fps: frames are mapped
scene.frame_start = 1
fps = json.load(open(os.path.join(RUN, "summary.json")))["fps"]
frames = sorted(int(n[6:11]) for n in os.listdir(RUN) if n.startswith("frame_") and n.endswith(".ply"))

result = bpy.ops.import_scene.pbf(directory=RUN)
check(result == {"FINISHED"}, f"import returned {result}")
name = "pbf " + os.path.basename(RUN)
root = bpy.data.objects[name]
particles = bpy.data.objects[name + " particles"]
surface = bpy.data.objects[name + " surface"]
volume = bpy.data.objects[name + " level set"]
check(scene.frame_end == 1 + math.ceil(frames[-1] / fps * 24 - 1e-6), f"frame_end {scene.frame_end}")

surface_counts = set()
for f in range(scene.frame_start, scene.frame_end + 1):
    scene.frame_set(f)
    k = min(math.floor((f - 1) / 24 * fps + 1e-6), frames[-1])
    ply, _ = read_ply(os.path.join(RUN, f"frame_{k:05d}.ply"))
    mesh = particles.data
    check(len(mesh.vertices) == len(ply), f"scene frame {f} (run frame {k}): {len(mesh.vertices)} points, PLY has {len(ply)}")
    if len(mesh.vertices) != len(ply):
        continue
    co = np.zeros(3 * len(ply), dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    check(np.array_equal(co.reshape(-1, 3), np.stack([ply["x"], ply["y"], ply["z"]], axis=1)),
          f"scene frame {f}: positions differ from frame_{k:05d}.ply")
    check(np.array_equal(attribute(mesh, "velocity", "vector", 3), np.stack([ply["vx"], ply["vy"], ply["vz"]], axis=1)),
          f"scene frame {f}: velocity differs from frame_{k:05d}.ply")
    check(np.array_equal(attribute(mesh, "density", "value", 1), ply["density"]),
          f"scene frame {f}: density differs from frame_{k:05d}.ply")
    check(np.array_equal(attribute(mesh, "id", "value", 1), ply["id"].astype(np.int32)),
          f"scene frame {f}: id differs from frame_{k:05d}.ply")
    # Y-up -> Z-up: world position of particle 0 is (x, -z, y).
    world = particles.matrix_world @ mesh.vertices[0].co
    expected = (ply["x"][0], -ply["z"][0], ply["y"][0])
    check(all(abs(world[i] - expected[i]) < 1e-5 for i in range(3)),
          f"scene frame {f}: particle 0 at {tuple(world)}, expected {expected} (Y-up to Z-up)")
    _, counts = read_ply(os.path.join(RUN, "surface", f"surface_{k:05d}.ply"))
    check(len(surface.data.vertices) == counts["vertex"] and len(surface.data.polygons) == counts["face"],
          f"scene frame {f}: surface has {len(surface.data.vertices)} vertices, surface_{k:05d}.ply {counts['vertex']}")
    surface_counts.add(len(surface.data.vertices))
    check(volume.data.filepath == os.path.join(RUN, "surface", f"levelset_{k:05d}.vdb"),
          f"scene frame {f}: level set {volume.data.filepath}")
check(len(surface_counts) > 1, f"the surface mesh did not change with the frame: {surface_counts}")
check(surface.data.polygons[0].use_smooth and surface.data.has_custom_normals, "surface without smooth normals")
check(surface.data.materials[0].name == "pbf Water", "surface without the water material")

# The level set's surface: grid "surface", threshold 0, evaluated at the last frame.
level_mesh = bpy.data.objects[name + " level set mesh"]
modifier = level_mesh.modifiers["pbf level set"]
check(modifier.grid_name == "surface" and modifier.threshold == 0.0, "Volume to Mesh settings")
level_mesh.hide_viewport = False
bpy.context.view_layer.update()
evaluated = level_mesh.evaluated_get(bpy.context.evaluated_depsgraph_get()).to_mesh()
check(len(evaluated.vertices) > 100, f"level set mesh has {len(evaluated.vertices)} vertices")
print(f"level set mesh: {len(evaluated.vertices)} vertices, surface mesh {len(surface.data.vertices)}")

# bodies.csv: two bodies, poses keyframed at their times, turned to Z-up.
bodies_run = os.path.join(WORK, "bodies_run")
os.makedirs(bodies_run, exist_ok=True)
json.dump({"fps": 24}, open(os.path.join(bodies_run, "summary.json"), "w"))
s = math.sqrt(0.5)
with open(os.path.join(bodies_run, "bodies.csv"), "w") as f:
    f.write("frame,time,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n")
    for k in range(3):
        f.write(f"{k},{k / 24},0,0.1,{0.5 - 0.1 * k},0.2,1,0,0,0,0,-2.4,0,0,0,0\n")
        f.write(f"{k},{k / 24},1,0.3,0.4,0.5,{s},0,{s},0,0,0,0,0,0,0\n")  # 90 degrees about pbf's y
check(bpy.ops.import_scene.pbf(directory=bodies_run) == {"FINISHED"}, "bodies import failed")
scene.frame_set(3)  # run frame 2
body0 = bpy.data.objects["pbf bodies_run body 0"].matrix_world.translation
check(max(abs(body0[i] - (0.1, -0.2, 0.3)[i]) for i in range(3)) < 1e-5, f"body 0 at {tuple(body0)}")
body1 = bpy.data.objects["pbf bodies_run body 1"].matrix_world
# pbf's y is Blender's z: a turn about pbf's y is a turn about Blender's z.
turned_x = body1.to_3x3() @ __import__("mathutils").Vector((1, 0, 0))
check(max(abs(turned_x[i] - (0, 1, 0)[i]) for i in range(3)) < 1e-5,
      f"body 1 turns x to {tuple(turned_x)}, expected (0, 1, 0)")

# Surfaces written as OBJ (`pbf mesh --format obj`) in a folder of their own,
# with no summary.json: the frame rate is given; the meshes are the PLY's.
obj_run = os.path.join(WORK, "obj_run")
check(bpy.ops.import_scene.pbf(directory=obj_run, fps=fps) == {"FINISHED"}, "OBJ surfaces import failed")
obj_surface = bpy.data.objects["pbf obj_run surface"]
for f, k in ((1, 0), (3, 2)):  # 24 fps scene, 30 fps run
    scene.frame_set(f)
    _, counts = read_ply(os.path.join(RUN, "surface", f"surface_{k:05d}.ply"))
    check(len(obj_surface.data.vertices) == counts["vertex"] and len(obj_surface.data.polygons) == counts["face"],
          f"OBJ surface at scene frame {f}: {len(obj_surface.data.vertices)} vertices, surface_{k:05d}.ply {counts['vertex']}")
    check(obj_surface.data.has_custom_normals, f"OBJ surface at scene frame {f}: the file's normals were not used")
try:
    bpy.ops.import_scene.pbf(directory=obj_run)
    check(False, "a run without fps imported")
except RuntimeError as e:
    check("no fps in summary.json" in str(e), f"unclear error without fps: {e}")

# A saved .blend keeps following the frames once reopened (load_post and
# frame-change handlers): frame 2 of a 24 fps scene shows run frame 1.
blend = os.path.join(WORK, "imported.blend")
bpy.ops.wm.save_as_mainfile(filepath=blend)
bpy.ops.wm.open_mainfile(filepath=blend)
scene = bpy.context.scene
scene.frame_set(2)
reopened = bpy.data.objects[name + " particles"]
ply, _ = read_ply(os.path.join(RUN, "frame_00001.ply"))
check(len(reopened.data.vertices) == len(ply) and reopened["pbf_frame"] == 1,
      f"after reopening the .blend: run frame {reopened.get('pbf_frame')}, {len(reopened.data.vertices)} points")
density = attribute(reopened.data, "density", "value", 1)
check(np.array_equal(density, ply["density"]), "after reopening the .blend: density differs")

# A directory that is not a run: a clear error naming it.
try:
    bpy.ops.import_scene.pbf(directory=os.path.join(WORK, "no_such_run"))
    check(False, "importing a missing directory did not fail")
except RuntimeError as e:
    check("no_such_run: no such directory" in str(e), f"unclear error: {e}")

if failures:
    print(f"blender: {len(failures)} checks failed")
    sys.exit(1)
print(f"blender: all checks passed (run frames 0-{frames[-1]} at {fps:g} fps in a 24 fps scene)")
