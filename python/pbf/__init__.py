"""pbf: Position Based Fluids water simulation (Macklin & Mueller 2013).

    import pbf
    world = pbf.World.from_scene("scenes/dam_break.json")
    world.step_frame()                     # one output frame (1 / fps seconds)
    x = world.positions                    # (N, 3) float32 view, in id order
    world.settings.iterations = 6          # live settings, validated
    world.bodies[0].position               # rigid bodies: pose, velocity, fluid force
    pbf.run("scenes/dam_break.json", out="out/dam", frames=60)   # what `pbf run` does

The simulation is the C++ library (the extension module pbf._pbf); this
package re-exports it and adds read_ply for the frames `pbf run` writes.
"""

from ._pbf import (
    Aabb,
    ArtificialPressureParams,
    EmitterDescription,
    EmitterList,
    FluidBlock,
    FluidBlockList,
    FluidParams,
    FrameReport,
    GuardParams,
    IoError,
    Motion,
    OutletDescription,
    OutletList,
    OutputParams,
    RigidBody,
    RigidBodyDescription,
    RigidBodyList,
    RunSummary,
    Scene,
    SceneError,
    Settings,
    SimulationParams,
    SolidDescription,
    SolidList,
    SolverParams,
    StageTimes,
    StateError,
    StateStatistics,
    Transform,
    World,
    WorldDef,
    __version__,
    hardware_threads,
    load_scene,
    parameters,
    run,
    set_threads,
    threads,
)
from .ply import read_ply

__all__ = [
    "Aabb", "ArtificialPressureParams", "EmitterDescription", "EmitterList", "FluidBlock",
    "FluidBlockList", "FluidParams", "FrameReport", "GuardParams", "IoError", "Motion", "OutletDescription",
    "OutletList", "OutputParams",
    "RigidBody", "RigidBodyDescription", "RigidBodyList", "RunSummary", "Scene", "SceneError", "Settings", "SimulationParams", "SolidDescription",
    "SolidList", "SolverParams", "StageTimes", "StateError", "StateStatistics", "Transform",
    "World", "WorldDef", "hardware_threads", "load_scene", "parameters", "read_ply", "run", "set_threads",
    "threads",
]

# Show the public names as pbf.X (in reprs, tracebacks and help()), not pbf._pbf.X.
for _name in __all__:
    _obj = globals()[_name]
    if isinstance(_obj, type) and _obj.__module__ == "pbf._pbf":
        try:
            _obj.__module__ = "pbf"
        except (AttributeError, TypeError):  # pragma: no cover - immutable type
            pass
del _name, _obj
