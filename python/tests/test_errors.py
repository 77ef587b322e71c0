"""Errors reach Python with the CLI's messages: the file, the field, the
frame and the particle."""

import pytest

import pbf


def test_missing_scene_file_names_the_file(tmp_path):
    missing = tmp_path / "nope.json"
    with pytest.raises(FileNotFoundError) as error:
        pbf.World.from_scene(missing)
    assert str(error.value) == f"{missing}: cannot open scene file (no such file)"
    with pytest.raises(FileNotFoundError, match="nope.json"):
        pbf.run(missing, out=tmp_path / "out")


def test_invalid_scene_names_file_and_field(tmp_path):
    scene = tmp_path / "bad.json"
    scene.write_text('{"domain": {"min": [0,0,0], "max": [1,1,1]}, "particle_radius": 0.01,'
                     ' "solver": {"iterations": 0}}')
    with pytest.raises(pbf.SceneError, match=r"bad.json: solver.iterations: must be in \[1, 100\]"):
        pbf.load_scene(scene)


def test_bad_override_names_the_field(dam_break):
    with pytest.raises(pbf.SceneError, match=r"solver.iterations: must be in \[1, 100\], got 0"):
        pbf.World.from_scene(dam_break, {"solver.iterations": 0})
    with pytest.raises(pbf.SceneError, match="solver.iteration: unknown key"):
        pbf.World.from_scene(dam_break, ["solver.iteration=3"])
    with pytest.raises(pbf.SceneError, match="expected FIELD=VALUE"):
        pbf.World.from_scene(dam_break, ["solver.iterations"])


def test_overrides_take_effect(dam_break):
    w = pbf.World.from_scene(dam_break, {"particle_radius": 0.02, "solver.iterations": 7,
                                         "gravity": [0, -1, 0], "solver.time_step": "fixed"})
    assert w.settings.iterations == 7 and w.settings.gravity == (0.0, -1.0, 0.0)
    assert w.settings.time_step == "fixed"
    assert w.step_frame().substeps == w.settings.substeps


def test_state_guard_failure_raises_state_error_naming_the_particle(dam_break):
    w = pbf.World.from_scene(dam_break, {"particle_radius": 0.02, "guard.max_speed": 0.3})
    with pytest.raises(pbf.StateError) as error:
        w.step_frames(10)
    e = error.value
    assert isinstance(e, RuntimeError)
    assert e.kind == "bad_state" and e.frame >= 1 and e.substep >= 1
    assert f"particle id {e.particle_id} " in str(e)
    assert "exceeds the limit of 0.3 m/s" in str(e) and "guard.max_speed" in str(e)
    assert str(e).startswith(f"bad state in frame {e.frame} substep {e.substep}")
    assert 0 <= e.particle_id < w.particle_count
    assert e.summary is None
    assert w.frame == e.frame - 1  # the failed frame was not counted


def test_nan_written_from_python_is_caught(small_world):
    small_world.positions[5] = float("nan")
    with pytest.raises(pbf.StateError, match="particle id 5 .*position is not finite") as error:
        small_world.step_frame()
    assert error.value.particle_id == 5 and error.value.substep == 0

