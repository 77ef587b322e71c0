"""pbf run importer for Blender: File > Import > pbf run.

Loads the output directory of `pbf run` (and `pbf mesh`) as animated objects:
particles (a vertex-only mesh with velocity, density and id attributes),
the surface mesh sequence, the level sets as a Volume, rigid bodies from
bodies.csv, all under one empty that turns pbf's Y-up into Blender's Z-up.
Scripts call `bpy.ops.import_scene.pbf(directory=RUN_DIR)`. Documented in
docs/clients.md.
"""

bl_info = {
    "name": "pbf run importer",
    "author": "pbf",
    "version": (1, 0, 0),
    "blender": (3, 4, 0),
    "location": "File > Import > pbf run",
    "description": "Particles, surfaces, level sets and rigid bodies of a pbf run, animated",
    "category": "Import-Export",
}

if "bpy" in locals():  # Blender's "Reload Scripts"
    import importlib

    for _module in ("ply", "run_dir", "bodies", "material", "objects"):
        if _module in locals():
            importlib.reload(locals()[_module])

import os

import bpy
from bpy.app.handlers import persistent
from bpy.props import BoolProperty, FloatProperty, StringProperty
from bpy_extras.io_utils import ImportHelper

from . import objects
from .ply import PlyError
from .run_dir import RunDirectory, RunError


@persistent
def _on_frame_change(scene, depsgraph=None):
    for obj in scene.objects:
        if "pbf_kind" in obj:
            try:
                objects.update(obj, scene)
            except (RunError, PlyError, OSError) as e:
                print(f"pbf: {obj.name}: {e}")


@persistent
def _on_load(*_):
    objects.forget_runs()
    for scene in bpy.data.scenes:
        _on_frame_change(scene)


class ImportPbfRun(bpy.types.Operator, ImportHelper):
    """Import the output directory of `pbf run` as animated objects"""

    bl_idname = "import_scene.pbf"
    bl_label = "Import pbf run"
    bl_options = {"REGISTER", "UNDO"}

    directory: StringProperty(name="Run directory", subtype="DIR_PATH",
                              description="Output directory of `pbf run` (frame_NNNNN.ply, surface/, ...)")
    filename_ext = ""
    use_filter_folder = True
    particles: BoolProperty(name="Particles", default=True,
                            description="frame_NNNNN.ply as points with velocity, density and id")
    surfaces: BoolProperty(name="Surfaces", default=True,
                           description="surface/surface_NNNNN.ply (or .obj) as one animated mesh")
    level_sets: BoolProperty(name="Level sets", default=True,
                             description="surface/levelset_NNNNN.vdb as a Volume and its surface")
    bodies: BoolProperty(name="Rigid bodies", default=True,
                         description="bodies.csv poses as keyframed empties")
    fps: FloatProperty(name="Run fps", default=0.0, min=0.0,
                       description="Frames per simulated second of the run; 0: from summary.json")

    def execute(self, context):
        try:
            run = RunDirectory(self.directory, self.fps)
            name = "pbf " + (os.path.basename(run.directory.rstrip(os.sep)) or "run")
            made = objects.create_run(context, run, name, self.particles, self.surfaces,
                                      self.level_sets, self.bodies)
        except (RunError, PlyError, OSError) as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        self.report({"INFO"}, f"{name}: {len(made) - 1} objects, run at {run.fps:g} fps")
        return {"FINISHED"}


def _menu(self, context):
    self.layout.operator(ImportPbfRun.bl_idname, text="pbf run")


def register():
    bpy.utils.register_class(ImportPbfRun)
    bpy.types.TOPBAR_MT_file_import.append(_menu)
    if _on_frame_change not in bpy.app.handlers.frame_change_pre:
        bpy.app.handlers.frame_change_pre.append(_on_frame_change)
    if _on_load not in bpy.app.handlers.load_post:
        bpy.app.handlers.load_post.append(_on_load)


def unregister():
    for handlers, handler in ((bpy.app.handlers.frame_change_pre, _on_frame_change),
                              (bpy.app.handlers.load_post, _on_load)):
        if handler in handlers:
            handlers.remove(handler)
    bpy.types.TOPBAR_MT_file_import.remove(_menu)
    bpy.utils.unregister_class(ImportPbfRun)
