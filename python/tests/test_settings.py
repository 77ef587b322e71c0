"""world.settings: live settings validated by the C++ library."""

import numpy as np
import pytest

import pbf


def test_settings_read_and_write(small_world):
    s = small_world.settings
    assert s.iterations == 4 and s.cfl == 0.4 and s.viscosity == 0.01
    assert s.gravity == (0.0, -9.81, 0.0)
    s.iterations = 6
    s.viscosity = 0.05
    s.gravity = (0, -3, 0)
    s["solver.artificial_pressure.k"] = 0.05
    assert small_world.settings.iterations == 6
    assert s.scorr_k == 0.05 and s["fluid.viscosity"] == 0.05
    report = small_world.step_frame()
    assert report.iterations == 6  # the solver ran what was set
    s.update({"solver.iterations": 3}, cfl=0.3)
    assert (s.iterations, s.cfl) == (3, 0.3)
    assert "solver.iterations" in s.keys() and s.as_dict()["solver.cfl"] == 0.3
    params = s.params()
    params.solver.iterations = 9
    small_world.settings = params
    assert s.iterations == 9


def test_invalid_setting_names_the_field_and_changes_nothing(small_world, dam_break):
    s = small_world.settings
    before = s.as_dict()
    with pytest.raises(pbf.SceneError) as error:
        s.iterations = 0
    assert str(error.value) == f"{dam_break}: solver.iterations: must be in [1, 100], got 0"
    assert isinstance(error.value, ValueError)
    with pytest.raises(ValueError, match="solver.restitution"):
        s.restitution = 2.0
    # all or nothing: the valid change in the same update is not applied either
    with pytest.raises(ValueError, match="fluid.viscosity"):
        s.update({"solver.iterations": 8, "fluid.viscosity": -1})
    with pytest.raises(ValueError, match="particle_radius: cannot change while the world runs"):
        s.particle_radius = 0.05
    with pytest.raises(TypeError, match="solver.iterations: expected an integer"):
        s.iterations = 2.5
    with pytest.raises(AttributeError):
        s.iteratons = 3  # a typo is not silently a new attribute
    with pytest.raises(KeyError, match="no setting"):
        s["solver.iteratons"] = 3
    assert s.as_dict() == before
    assert small_world.step_frame().iterations == 4


def _other_valid_value(row, settings):
    """A value of the parameter's type inside its range, different from the current one."""
    current = settings[row["path"]]
    kind = row["type"]
    if kind in ("float", "int"):
        low = row["min"]
        high = row["max"] if not isinstance(row["max"], str) else settings[row["max"]]
        for fraction in (0.5, 0.25, 0.75):
            value = low + fraction * (high - low)
            value = int(value) if kind == "int" else value
            if value != current:
                return value
    if kind == "vec3":
        return (0.5, -3.0, 0.25)
    if kind == "choice":
        return "fixed" if current == "adaptive" else "adaptive"
    raise AssertionError(f"no value for {row}")


def test_every_live_parameter_is_readable_and_settable(small_world):
    """Walks the parameter table: every live parameter the CLI's --set accepts can be read and
    written through world.settings, by path and by attribute, and the World runs what was set
    (read back from World::settings(), not from the proxy). Fails for a row that the settings
    proxy forgets (a KeyError) or a write that does not reach the World."""
    rows = pbf.parameters()
    live = [r for r in rows if r["live"]]
    assert {r["path"] for r in live} >= {
        "solver.warm_start", "solver.over_relaxation", "solver.max_density_error",
        "solver.min_iterations", "solver.max_iterations", "fluid.viscosity", "gravity"}
    s = small_world.settings
    assert set(s.keys()) == {r["path"] for r in rows}
    for row in live:
        value = _other_valid_value(row, s)
        s[row["path"]] = value
        expected = pytest.approx(value) if row["type"] == "float" else value
        assert s[row["path"]] == expected, row["path"]
        assert getattr(s, row["attribute"]) == expected, row["attribute"]
        # The World itself holds the new value.
        assert getattr(_group(s.params(), row["path"]), row["path"].split(".")[-1]) == expected
    for row in rows:
        if not row["live"]:
            current = s[row["path"]]
            if row["type"] == "box":
                changed = pbf.Aabb(tuple(v - 0.1 for v in current.min), current.max)
            else:
                changed = current * 0.9
            with pytest.raises(ValueError, match=row["path"] + ": cannot change while the world runs"):
                s[row["path"]] = changed
            assert s[row["path"]] == current


# For each live setting: a value to set, and the settings under which it
# acts on the small dam break's first frames (a tolerance for the iteration
# bounds, fixed substeps for `substeps`, surface tension for the walls'
# adhesion, a small CFL for the substep cap, ...).
_STEP_CASES = {
    "gravity": ((0.0, -5.0, 0.0), {}),
    "fluid.rest_density": (1100.0, {}),
    "fluid.viscosity": (0.1, {}),
    "fluid.kinematic_viscosity": (1e-3, {}),
    "fluid.vorticity": (0.3, {}),
    "fluid.surface_tension": (0.0728, {}),
    "solver.iterations": (6, {}),
    "solver.max_density_error": (0.0002, {}),
    "solver.min_iterations": (6, {"solver.max_density_error": 0.05}),
    "solver.max_iterations": (3, {"solver.max_density_error": 1e-5}),
    "solver.over_relaxation": (1.2, {}),
    "solver.warm_start": (0.5, {}),
    "solver.relaxation": (0.5, {}),
    "solver.consistent_correction": (0.5, {}),
    "solver.artificial_pressure.k": (0.1, {}),
    "solver.artificial_pressure.n": (2, {}),
    "solver.artificial_pressure.dq": (0.1, {}),
    "solver.time_step": ("fixed", {}),
    "solver.cfl": (0.05, {}),
    "solver.max_time_step": (1e-3, {}),
    "solver.max_substeps": (2, {"solver.cfl": 0.05}),
    "solver.depth_limit": (0.01, {}),
    "solver.substeps": (3, {"solver.time_step": "fixed"}),
    "solver.restitution": (0.8, {}),
    "solver.friction": (1.0, {}),
    "solver.wall_adhesion": (0.9, {"fluid.surface_tension": 0.0728}),
}


def test_every_live_setting_reaches_the_step(dam_break):
    """Two worlds from the same scene and settings, one of them with a live setting changed
    through world.settings: their next frames differ. A setting that is stored and read back
    but does not reach the solver (say, the solver's constants not rebuilt after a write)
    leaves the two bit for bit equal."""
    live = {r["path"] for r in pbf.parameters() if r["live"]}
    assert live == set(_STEP_CASES), "a live setting without a case here: add one"
    same = []
    for path, (value, context) in _STEP_CASES.items():
        worlds = []
        for changed in (False, True):
            w = pbf.World.from_scene(dam_break, {"particle_radius": 0.02})
            w.settings.update(context)
            if changed:
                w.settings[path] = value
            w.step_frames(2)
            worlds.append(w)
        if np.array_equal(worlds[0].positions, worlds[1].positions):
            same.append(path)
    assert same == [], f"changing these did not change the step: {same}"


def _group(params, path):
    """The struct of SimulationParams that holds the parameter at `path`."""
    for part in path.split(".")[:-1]:
        params = getattr(params, part)
    return params


def test_surface_tension_and_adhesion(small_world):
    # Surface tension is a live setting like the others (off by default);
    # adhesion belongs to the definition's solids and bodies.
    s = small_world.settings
    assert s.surface_tension == 0.0 and s.wall_adhesion == 0.0
    s.surface_tension = 0.0728
    s["solver.wall_adhesion"] = 0.5
    assert s["fluid.surface_tension"] == pytest.approx(0.0728) and s.wall_adhesion == 0.5
    small_world.step_frame()
    with pytest.raises(pbf.SceneError, match="fluid.surface_tension"):
        s.surface_tension = -1.0
    solid = pbf.SolidDescription.sphere((0.1, 0.1, 0.1), 0.05)
    solid.adhesion = 0.7
    assert solid.adhesion == pytest.approx(0.7)
    body = pbf.RigidBodyDescription(solid, density=500.0)
    assert body.adhesion == pytest.approx(0.7)
    body.adhesion = 0.2
    assert body.shape.adhesion == pytest.approx(0.2)
