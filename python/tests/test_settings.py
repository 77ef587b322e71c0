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
