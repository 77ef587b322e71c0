"""pbf.World: stepping, reports, worlds built in code."""

import numpy as np
import pytest

import pbf
from conftest import require_device


def test_import_exposes_the_interface():
    for name in ("World", "WorldDef", "FluidBlock", "SolidDescription", "EmitterDescription",
                 "SimulationParams", "SolverParams", "FluidParams", "run", "load_scene",
                 "SceneError", "IoError", "StateError", "read_ply"):
        assert hasattr(pbf, name), name
    assert pbf.__version__.count(".") == 2
    assert issubclass(pbf.SceneError, ValueError)
    assert issubclass(pbf.IoError, OSError)
    assert issubclass(pbf.StateError, RuntimeError)
    assert pbf.World.__module__ == "pbf"


def test_step_advances_frame_and_time_and_keeps_density(small_world):
    w = small_world
    n = w.particle_count
    assert n > 1000 and w.frame == 0 and w.time == 0.0
    assert w.positions.shape == (n, 3)
    report = w.step_frame()
    assert report.frame == 1 == w.frame
    assert report.time == pytest.approx(1 / 30) and w.time == pytest.approx(1 / 30)
    assert report.substeps >= 1 and report.iterations == 4 and report.step_ms > 0
    reports = w.step_frames(4)
    assert [r.frame for r in reports] == [2, 3, 4, 5]
    assert w.time == pytest.approx(5 / 30)
    stats = reports[-1].statistics
    assert stats.particles == n and stats.escaped == 0 and stats.inside_solid == 0
    # PBF keeps the liquid incompressible: compression error ~0.1 %, and the
    # densities of particles inside the column sit at rest density.
    assert stats.average_density_error < 0.01
    assert stats.max_density_error < 0.1
    assert stats.kinetic_energy > 0 and stats.max_speed > 0.3  # the column is collapsing
    inner = np.median(w.densities)
    assert 950 < inner < 1030
    assert w.report().frame == 5
    assert w.report().statistics.particles == n


def test_world_from_definition_in_code():
    d = pbf.WorldDef(name="box")
    d.simulation.domain = ((0, 0, 0), (0.4, 0.4, 0.1))
    d.simulation.particle_radius = 0.01
    d.simulation.fluid.viscosity = 0.02
    d.fluid_blocks.append(pbf.FluidBlock((0, 0, 0), (0.1, 0.2, 0.1)))
    d.solids.append(pbf.SolidDescription.box(((0.3, 0, 0), (0.4, 0.05, 0.1))))
    d.emitters.append(pbf.EmitterDescription((0.2, 0.35, 0.05), radius=0.02, speed=1.0))
    assert d.validate() == ""
    assert d.count_particles() == 5 * 10 * 5
    w = pbf.World(d)
    assert w.particle_count == 250 and w.definition.name == "box"
    assert w.settings.viscosity == 0.02
    assert len(w.solids) == 1 and "box" in w.solids[0]
    w.step_frames(3)
    assert w.particle_count > 250  # the emitter poured
    assert w.positions.shape == (w.particle_count, 3)
    x = w.positions
    assert (x >= 0).all() and (x[:, 0] <= 0.4).all() and (x[:, 1] <= 0.4).all()


def test_definition_lists_and_conversions():
    d = pbf.WorldDef(fluid_blocks=[pbf.FluidBlock(box=np.array([[0, 0, 0], [0.1, 0.1, 0.1]]))])
    assert len(d.fluid_blocks) == 1
    assert d.fluid_blocks[0].box.max == (0.1, 0.1, 0.1)
    d.fluid_blocks[0].velocity = [1, 0, 0]  # lists and arrays are points
    assert d.fluid_blocks[0].velocity == (1.0, 0.0, 0.0)
    d.simulation.gravity = np.array([0, -3.5, 0])
    assert d.simulation.gravity == (0.0, -3.5, 0.0)
    d.simulation.solver.time_step = "fixed"
    with pytest.raises(pbf.SceneError, match="solver.time_step"):
        d.simulation.solver.time_step = "sometimes"
    mesh = pbf.SolidDescription.mesh("bunny.obj", scale=0.5, translation=(1, 0, 0))
    assert mesh.kind == "mesh" and mesh.transform.scale == (0.5, 0.5, 0.5)
    assert pbf.Aabb((0, 0, 0), (1, 2, 3)).extent == (1.0, 2.0, 3.0)


def test_world_rejects_invalid_definition():
    d = pbf.WorldDef(name="bad")
    d.simulation.particle_radius = 0.01
    d.fluid_blocks.append(pbf.FluidBlock((0, 0, 0), (2, 0.1, 0.1)))  # beyond the domain
    with pytest.raises(pbf.SceneError, match=r"^bad: fluid_blocks\[0\]"):
        pbf.World(d)


def test_arrays_follow_each_particle_by_id(small_world):
    """positions[k] is particle k in every frame, although the CPU solver reorders its particles
    by grid cell every step: from one frame to the next each particle moves by about its
    velocity times the frame's duration, never by a jump to another particle's place."""
    w = small_world
    w.step_frames(3)  # the column is moving and the solver has reordered its particles
    x0 = np.array(w.positions, dtype=np.float64)
    v0 = np.array(w.velocities, dtype=np.float64)
    dt = w.frame_duration
    w.step_frame()
    moved = np.linalg.norm(np.array(w.positions) - x0, axis=1)
    expected = np.linalg.norm(v0, axis=1) * dt
    # The front moves at up to ~2.5 m/s; a particle that swapped places with
    # another would jump by up to the column's size (tenths of a metre).
    assert moved.max() < 0.1
    assert np.abs(moved - expected).max() < 0.02


def test_device_choice(dam_break):
    """The reference backend runs when asked for, not only its name: it keeps its particles in
    their order (no sort, no reorder stage) and computes the CPU solver's physics."""
    require_device("reference")
    reference = pbf.World.from_scene(dam_break, {"particle_radius": 0.02}, device="reference")
    cpu = pbf.World.from_scene(dam_break, {"particle_radius": 0.02}, device="cpu")
    assert reference.device == "reference" and cpu.device == "cpu"
    on_reference, on_cpu = reference.step_frame(), cpu.step_frame()
    assert on_reference.stage_ms.reorder == 0.0 and on_reference.stage_ms.grid_build == 0.0
    assert on_cpu.stage_ms.reorder > 0.0
    assert np.abs(reference.positions - cpu.positions).max() < 1e-3


def test_unknown_device_is_refused(dam_break):
    with pytest.raises(ValueError, match='device: must be cpu, reference, cuda or cuda-on-cpu, got "gpu"'):
        pbf.World.from_scene(dam_break, device="gpu")


def test_add_particles(small_world):
    w = small_world
    n = w.particle_count
    w.add_particles(np.array([[1.2, 0.8, 0.2], [1.3, 0.8, 0.2]]), [[0, 0, 0], [0.5, 0, 0]])
    assert w.particle_count == n + 2
    np.testing.assert_array_equal(w.positions[n:], np.float32([[1.2, 0.8, 0.2], [1.3, 0.8, 0.2]]))
    assert w.ids[-1] == n + 1
    w.step_frame()
    # The new particles fall freely for one frame: y = 0.8 - g t^2 / 2.
    assert w.positions[n, 1] == pytest.approx(0.8 - 0.5 * 9.81 / 30**2, abs=2e-3)
    with pytest.raises(ValueError, match=r"\(N, 3\)"):
        w.add_particles(np.zeros((2, 2)))
    with pytest.raises(ValueError, match="velocities"):
        w.add_particles(np.zeros((2, 3)) + 0.5, np.zeros((3, 3)))


def test_a_solid_with_a_prescribed_motion_stirs_the_water():
    d = pbf.WorldDef(name="mixer")
    d.simulation.domain = ((0, 0, 0), (0.4, 0.25, 0.4))
    d.simulation.particle_radius = 0.01
    d.fluid_blocks.append(pbf.FluidBlock((0, 0, 0), (0.4, 0.15, 0.4)))
    paddle = pbf.SolidDescription.box((0.1, 0.02, 0.19), (0.3, 0.14, 0.21))
    paddle.motion = pbf.Motion.rotate(axis=(0, 1, 0), speed=120)
    d.solids.append(paddle)
    assert d.solids[0].motion.kind == "rotate"
    # A quarter turn about +y in 0.75 s takes +x to -z (about the pivot).
    at, velocity, spin = pbf.Motion.rotate(speed=120).pose_at(0.75, pivot=(0.2, 0, 0.2))
    assert at == pytest.approx((0.2 - 0.2, 0.0, 0.2 + 0.2), abs=1e-5)
    assert spin[1] == pytest.approx(np.radians(120))
    w = pbf.World(d)
    w.step_frames(20)
    x = w.positions - (0.2, 0.0, 0.2)
    v = w.velocities
    angular = np.sum(x[:, 2] * v[:, 0] - x[:, 0] * v[:, 2])
    assert angular > 0  # the water turns with the paddle (+y)
    assert w.report().statistics.inside_solid == 0
    with pytest.raises(ValueError, match=r"solids\[0\].motion"):
        w.set_solid_motion(0, position=(0, 0, 0))
    bad = pbf.SolidDescription.box((0.1, 0.02, 0.19), (0.3, 0.14, 0.21))
    bad.motion = pbf.Motion.keyframes([(1.0, (0, 0, 0)), (0.5, (0.1, 0, 0))])
    d.solids[0] = bad
    assert d.validate().startswith("solids[0].motion.keys[1].time: keyframes must be in")


def test_wave_makers_compute_their_stroke():
    piston = pbf.Motion.piston(wave_height=0.02, period=1.0, depth=0.2)
    assert piston.kind == "piston"
    assert "H / S = 1.015" in piston.describe() and "stroke 0.0197 m" in piston.describe()
    flap = pbf.Motion.flap(wave_height=0.02, period=1.0, depth=0.2, pivot=(0.05, 0, 0))
    assert flap.kind == "flap" and "flap wave maker" in flap.describe()
    d = pbf.WorldDef(name="flume")
    d.simulation.domain = ((0, 0, 0), (1.0, 0.4, 0.1))
    d.simulation.particle_radius = 0.01
    d.fluid_blocks.append(pbf.FluidBlock((0.1, 0, 0), (1.0, 0.2, 0.1)))
    paddle = pbf.SolidDescription.box((0.02, 0, 0), (0.08, 0.35, 0.1))
    paddle.motion = pbf.Motion.piston(wave_height=0.5, period=1.0, depth=0.2)
    d.solids.append(paddle)
    assert d.validate().startswith("solids[0].motion.wave_height: 0.5 m waves of 1 s break")


def test_outlets_drain_the_water_and_the_views_keep_the_ids_that_stay():
    d = pbf.WorldDef(name="drain")
    d.simulation.domain = ((0, 0, 0), (0.4, 0.3, 0.2))
    d.simulation.particle_radius = 0.01
    d.fluid_blocks.append(pbf.FluidBlock((0, 0, 0), (0.2, 0.2, 0.2)))
    d.outlets.append(pbf.OutletDescription.plane((0.3, 0, 0), (1, 0, 0)))
    d.outlets.append(pbf.OutletDescription.box((0.08, 0.08, 0.08), (0.12, 0.12, 0.12)))
    w = pbf.World(d)
    reports = w.step_frames(6)
    removed = sum(r.removed for r in reports)
    assert removed == w.removed_particles > 8  # the hole's 8 and the drain's
    assert w.particle_count == 1000 - removed and w.emitted_particles == 0
    ids = w.ids
    assert ids.shape == (w.particle_count,)
    assert (np.diff(ids.astype(np.int64)) > 0).all() and ids[-1] >= w.particle_count  # gaps
    assert (w.positions[:, 0] <= 0.3).all()
    # Rows are particles by id: the row of the highest id, moved into the
    # drain, leaves at the next step; the others stay.
    last = int(ids[-1])
    w.positions[-1] = (0.35, 0.05, 0.1)
    w.step_frame()
    assert last not in set(w.ids.tolist())
    bad = pbf.WorldDef(name="bad")
    bad.simulation = d.simulation
    bad.fluid_blocks.append(pbf.FluidBlock((0, 0, 0), (0.2, 0.2, 0.2)))
    bad.outlets.append(pbf.OutletDescription.plane((0, 0, 0), (0, 0, 0)))
    assert bad.validate() == "outlets[0].normal: must be a non-zero vector"
