"""The objects of an imported run and how they follow the scene frame.

Every object that shows a frame sequence carries custom properties saying
where its files are (`pbf_kind`, `pbf_run_dir`, `pbf_fps`,
`pbf_frame_start`); a frame-change handler (see __init__.py) loads the run
frame that belongs to the scene frame. So a saved .blend keeps working, and
the Alembic exporter, which steps through the frames, sees every frame.
"""

import math
import os

import bpy
import numpy as np

from . import ply
from .material import water_material
from .run_dir import RunDirectory, bpy_path, run_frame, scene_fps

_runs = {}  # (directory, fps) -> RunDirectory


def run_of(obj):
    key = (bpy_path(obj["pbf_run_dir"]), float(obj["pbf_fps"]))
    run = _runs.get(key)
    if run is None:
        run = _runs[key] = RunDirectory(key[0], key[1])
    return run


def forget_runs():
    _runs.clear()


def _sequence(run, kind):
    return {"particles": run.particles, "surface": run.surfaces, "level_set": run.level_sets}[kind]


def _tag(obj, kind, run, frame_start):
    obj["pbf_kind"] = kind
    obj["pbf_run_dir"] = run.directory
    obj["pbf_fps"] = run.fps
    obj["pbf_frame_start"] = frame_start
    obj["pbf_frame"] = -1


def set_particles(mesh, frame):
    """A vertex-only mesh: one vertex per particle with the point attributes
    velocity (vector), density (float) and id (int) of the PLY frame."""
    mesh.clear_geometry()  # also drops the previous frame's attributes
    n = len(frame.vertex)
    mesh.vertices.add(n)
    mesh.vertices.foreach_set("co", frame.vectors("x", "y", "z").ravel())
    if frame.has("vx", "vy", "vz"):
        a = mesh.attributes.new("velocity", "FLOAT_VECTOR", "POINT")
        a.data.foreach_set("vector", frame.vectors("vx", "vy", "vz").ravel())
    if frame.has("density"):
        a = mesh.attributes.new("density", "FLOAT", "POINT")
        a.data.foreach_set("value", frame.vertex["density"].astype(np.float32))
    if frame.has("id"):
        # Blender has no unsigned attribute; ids stay below 2^31.
        a = mesh.attributes.new("id", "INT", "POINT")
        a.data.foreach_set("value", frame.vertex["id"].astype(np.int32))
    mesh.update()


def _read_obj(path):
    """v / vn / f lines of an OBJ written by `pbf mesh --format obj`."""
    vertices, normals, faces = [], [], []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                vertices.append(line.split()[1:4])
            elif line.startswith("vn "):
                normals.append(line.split()[1:4])
            elif line.startswith("f "):
                faces.append([int(w.split("/")[0]) - 1 for w in line.split()[1:4]])
    dtype = [("x", "<f4"), ("y", "<f4"), ("z", "<f4")]
    vertex = np.zeros(len(vertices), dtype=dtype + ([("nx", "<f4"), ("ny", "<f4"), ("nz", "<f4")]
                                                       if len(normals) == len(vertices) else []))
    v = np.array(vertices, dtype=np.float32).reshape(-1, 3)
    vertex["x"], vertex["y"], vertex["z"] = v[:, 0], v[:, 1], v[:, 2]
    if "nx" in vertex.dtype.names:
        n = np.array(normals, dtype=np.float32).reshape(-1, 3)
        vertex["nx"], vertex["ny"], vertex["nz"] = n[:, 0], n[:, 1], n[:, 2]
    return ply.Ply(vertex, np.array(faces, dtype=np.uint32).reshape(-1, 3))


def set_surface(mesh, frame):
    """Triangles, smooth-shaded with the file's vertex normals when it has them."""
    mesh.clear_geometry()
    triangles = frame.triangles if frame.triangles is not None else np.zeros((0, 3), np.uint32)
    mesh.vertices.add(len(frame.vertex))
    mesh.vertices.foreach_set("co", frame.vectors("x", "y", "z").ravel())
    t = len(triangles)
    mesh.loops.add(3 * t)
    mesh.loops.foreach_set("vertex_index", triangles.astype(np.int32).ravel())
    mesh.polygons.add(t)
    mesh.polygons.foreach_set("loop_start", np.arange(0, 3 * t, 3, dtype=np.int32))
    mesh.polygons.foreach_set("loop_total", np.full(t, 3, dtype=np.int32))
    mesh.polygons.foreach_set("use_smooth", np.ones(t, dtype=bool))
    mesh.update(calc_edges=True)
    if frame.has("nx", "ny", "nz") and t:
        if hasattr(mesh, "use_auto_smooth"):  # Blender < 4.1 needs it for custom normals
            mesh.use_auto_smooth = True
        mesh.normals_split_custom_set_from_vertices(frame.vectors("nx", "ny", "nz"))


def _read_surface(path):
    return _read_obj(path) if path.endswith(".obj") else ply.read_ply(path)


def update(obj, scene):
    """Shows the run frame of the scene's current frame; returns it (or None)."""
    kind = obj.get("pbf_kind")
    run = run_of(obj)
    wanted = run_frame(scene.frame_current + scene.frame_subframe, obj["pbf_frame_start"],
                       scene_fps(scene), run.fps)
    sequence = _sequence(run, kind)
    frame = sequence.at_or_before(wanted)
    if frame is None or frame == obj.get("pbf_frame"):
        return frame
    path = sequence.files[frame]
    if kind == "particles":
        set_particles(obj.data, ply.read_ply(path))
    elif kind == "surface":
        set_surface(obj.data, _read_surface(path))
    elif kind == "level_set":
        obj.data.filepath = path
    obj["pbf_frame"] = frame
    return frame


def _points_modifier(obj, radius):
    """Geometry Nodes 'Mesh to Points' so the particles render as spheres of
    the particle radius (a vertex-only mesh renders nothing) in the water material."""
    group = bpy.data.node_groups.new("pbf points", "GeometryNodeTree")
    if hasattr(group, "interface"):  # Blender 4
        group.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
        group.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    else:
        group.inputs.new("NodeSocketGeometry", "Geometry")
        group.outputs.new("NodeSocketGeometry", "Geometry")
    nodes, links = group.nodes, group.links
    source = nodes.new("NodeGroupInput")
    points = nodes.new("GeometryNodeMeshToPoints")
    points.inputs["Radius"].default_value = radius
    material = nodes.new("GeometryNodeSetMaterial")
    material.inputs["Material"].default_value = water_material()
    sink = nodes.new("NodeGroupOutput")
    links.new(source.outputs[0], points.inputs["Mesh"])
    links.new(points.outputs["Points"], material.inputs["Geometry"])
    links.new(material.outputs["Geometry"], sink.inputs[0])
    modifier = obj.modifiers.new("pbf points", "NODES")
    modifier.node_group = group
    return modifier


def create_run(context, run, name, particles=True, surfaces=True, level_sets=True, bodies=True):
    """Builds the objects of `run` in a new collection; returns the root empty."""
    from .bodies import keyframe_body, read_bodies
    from .run_dir import scene_frame

    scene = context.scene
    start = scene.frame_start
    collection = bpy.data.collections.new(name)
    scene.collection.children.link(collection)

    # pbf is Y-up, Blender Z-up: one +90 degree turn about X on the root maps
    # (x, y, z) to (x, -z, y); the objects' data stay as in the files.
    root = bpy.data.objects.new(name, None)
    root.empty_display_type = "ARROWS"
    root.empty_display_size = 0.1
    root.rotation_euler = (math.pi / 2, 0.0, 0.0)
    root["pbf_run_dir"] = run.directory
    collection.objects.link(root)

    def add(obj):
        obj.parent = root
        collection.objects.link(obj)
        return obj

    made = {"root": root}
    if particles and run.particles:
        obj = add(bpy.data.objects.new(name + " particles", bpy.data.meshes.new(name + " particles")))
        _tag(obj, "particles", run, start)
        if run.particle_radius > 0:
            _points_modifier(obj, run.particle_radius)
        made["particles"] = obj
    if surfaces and run.surfaces:
        obj = add(bpy.data.objects.new(name + " surface", bpy.data.meshes.new(name + " surface")))
        obj.data.materials.append(water_material())
        _tag(obj, "surface", run, start)
        made["surface"] = obj
    if level_sets and run.level_sets:
        volume = bpy.data.volumes.new(name + " level set")
        obj = add(bpy.data.objects.new(name + " level set", volume))
        _tag(obj, "level_set", run, start)
        obj.display_type = "BOUNDS"  # the grid is a distance, not a density to draw
        obj.hide_render = True
        made["level_set"] = obj
        # The surface of the level set: grid "surface", iso-value 0 (Blender's
        # defaults, grid "density" and threshold 0.1, give an empty mesh).
        mesh_obj = add(bpy.data.objects.new(name + " level set mesh", bpy.data.meshes.new(name + " level set mesh")))
        modifier = mesh_obj.modifiers.new("pbf level set", "VOLUME_TO_MESH")
        modifier.object = obj
        modifier.grid_name = "surface"
        modifier.threshold = 0.0
        modifier.resolution_mode = "GRID"
        modifier.use_smooth_shade = True
        mesh_obj.data.materials.append(water_material())
        if "surface" in made:  # the same surface as the meshes: shown on request only
            mesh_obj.hide_viewport = True
            mesh_obj.hide_render = True
        made["level_set_mesh"] = mesh_obj
    poses = read_bodies(run.bodies) if bodies and run.bodies else {}
    if poses:
        for body, samples in sorted(poses.items()):
            obj = add(bpy.data.objects.new(f"{name} body {body}", None))
            obj.empty_display_type = "CUBE"
            obj.empty_display_size = 0.05
            keyframe_body(obj, samples, lambda t: scene_frame(t, start, scene_fps(scene)))
            made[f"body {body}"] = obj

    # The timeline covers the run: its last frame at its time.
    last = max([s.frames[-1] for s in (run.particles, run.surfaces, run.level_sets) if s] + [0])
    end_time = max([last / run.fps] + [samples[-1][0] for samples in poses.values()])
    scene.frame_end = start + math.ceil(end_time * scene_fps(scene) - 1e-6)
    for obj in made.values():
        if "pbf_kind" in obj:
            update(obj, scene)
    return made
