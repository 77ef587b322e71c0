"""A pbf run as one animated Alembic file (for Maya, Houdini, Cinema 4D ...),
through the Blender add-on, headless:

    blender -b --factory-startup --python blender/pbf_to_alembic.py -- RUN_DIR OUT.abc

The scene takes the run's frame rate, so every run frame is one Alembic
sample. The file holds the particles (points with their velocity), the
surface mesh sequence and the rigid bodies as animated transforms; level sets
are left out (Alembic has no volumes: use the .vdb files). Exits non-zero
with a message naming the file for a bad run directory, and with status 3
when this Blender has no Alembic exporter: Debian's blender package (3.4.1)
is built without Alembic; Blender's own builds (blender.org) have it.
"""

import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


def main(argv):
    if len(argv) != 2:
        print("usage: blender -b --factory-startup --python pbf_to_alembic.py -- RUN_DIR OUT.abc",
              file=sys.stderr)
        return 2
    run_dir, out = (os.path.abspath(a) for a in argv)
    if not bpy.app.build_options.alembic:
        print(f"pbf_to_alembic: this Blender ({bpy.app.version_string}, {bpy.app.binary_path}) "
              "was built without Alembic (Debian's blender package is); use a Blender from "
              "blender.org", file=sys.stderr)
        return 3
    bpy.ops.wm.read_factory_settings(use_empty=True)
    import io_scene_pbf
    from io_scene_pbf.run_dir import RunDirectory, RunError

    if not hasattr(bpy.types, "IMPORT_SCENE_OT_pbf"):  # unless installed as an add-on
        io_scene_pbf.register()
    try:
        fps = RunDirectory(run_dir).fps
    except RunError as e:
        print(f"pbf_to_alembic: {e}", file=sys.stderr)
        return 1
    scene = bpy.context.scene
    scene.render.fps = max(1, round(fps))
    scene.render.fps_base = scene.render.fps / fps
    scene.frame_start = 0  # scene frame k = run frame k
    try:
        bpy.ops.import_scene.pbf(directory=run_dir, level_sets=False)
    except RuntimeError as e:
        print(f"pbf_to_alembic: {e}", file=sys.stderr)
        return 1
    # Alembic stores the particles as the vertex-only mesh, not the spheres
    # the points modifier makes for rendering.
    for obj in scene.objects:
        for modifier in obj.modifiers:
            if modifier.type == "NODES" and modifier.name == "pbf points":
                modifier.show_render = modifier.show_viewport = False
    bpy.ops.wm.alembic_export(filepath=out, start=scene.frame_start, end=scene.frame_end,
                              selected=False, flatten=False, evaluation_mode="RENDER",
                              as_background_job=False)
    if not os.path.isfile(out):
        print(f"pbf_to_alembic: {out}: Blender wrote no file", file=sys.stderr)
        return 1
    print(f"pbf_to_alembic: {run_dir} -> {out} (frames {scene.frame_start}-{scene.frame_end} at {fps:g} fps)")
    return 0


argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
status = main(argv)
if status:
    sys.exit(status)
