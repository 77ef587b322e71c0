"""world.settings: live settings validated by the C++ library."""

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
