"""pbf.run: what `pbf run` does."""

import json

import numpy as np
import pytest

import pbf


def test_run_writes_frames_and_summary(dam_break, tmp_path):
    out = tmp_path / "dam"
    summary = pbf.run(dam_break, out=out, frames=4, overrides={"particle_radius": 0.02})
    for k in range(5):
        assert (out / f"frame_{k:05d}.ply").is_file()
    assert not (out / "frame_00005.ply").exists()
    assert (out / "stats.csv").read_text().count("\n") == 1 + 5  # header + frames 0..4
    on_disk = json.loads((out / "summary.json").read_text())
    assert summary.frames == on_disk["frames"] == 4
    assert summary.particles == on_disk["particles"] > 1000
    assert summary.max_density_error == on_disk["max_density_error"]
    assert summary.average_density_error < 0.01
    assert summary.particle_steps_per_second > 0 and summary.wall_seconds > 0
    assert summary.max_escaped == 0 and summary.error is None
    assert summary.checkpoint == str(out / "checkpoint.pbfck")
    assert summary.directory == str(out)
    assert summary.as_dict()["frames"] == 4
    # The last frame equals a World stepped to the same frame.
    world = pbf.World.from_scene(dam_break, {"particle_radius": 0.02})
    world.step_frames(4)
    last = pbf.read_ply(out / "frame_00004.ply")
    assert np.array_equal(last["x"], world.positions[:, 0])


def test_run_writes_vtk_when_the_scene_asks(dam_break, tmp_path):
    out = tmp_path / "vtk"
    pbf.run(dam_break, out=out, frames=2, overrides={"particle_radius": 0.02, "output.vtk": True})
    for k in range(3):
        assert (out / f"frame_{k:05d}.vtu").is_file()
    listing = (out / "particles.pvd").read_text()
    assert listing.count("<DataSet ") == 3
    fps = json.loads((out / "summary.json").read_text())["fps"]
    assert f'timestep="{2 / fps!r}" part="0" file="frame_00002.vtu"' in listing
    assert pbf.load_scene(dam_break).output.vtk is False  # off unless asked for


def test_run_raises_state_error_with_summary(dam_break, tmp_path):
    with pytest.raises(pbf.StateError, match="particle id") as error:
        pbf.run(dam_break, out=tmp_path, frames=5,
                overrides=["particle_radius=0.02", "guard.max_speed=0.3"])
    summary = error.value.summary
    assert summary.frames == 0 and summary.error == str(error.value)
    assert "the run stopped: frames up to 0 are written" in str(error.value)
    assert (tmp_path / "frame_00000.ply").is_file()
    assert "error" in json.loads((tmp_path / "summary.json").read_text())


def test_run_a_world_defined_in_code(tmp_path):
    d = pbf.WorldDef(name="drop")
    d.simulation.domain = ((0, 0, 0), (0.3, 0.3, 0.1))
    d.fluid_blocks.append(pbf.FluidBlock((0.1, 0.1, 0.0), (0.2, 0.2, 0.1)))
    seen = []
    summary = pbf.run(d, out=tmp_path, frames=2, on_frame=lambda r: seen.append(r.frame))
    assert seen == [0, 1, 2] and summary.frames == 2 and summary.scene == "drop"
    assert (tmp_path / "frame_00002.ply").is_file()


def test_run_stops_when_on_frame_raises(dam_break, tmp_path):
    def stop(report):
        if report.frame == 1:
            raise KeyError("stop here")

    with pytest.raises(KeyError, match="stop here"):
        pbf.run(dam_break, out=tmp_path, frames=30, overrides={"particle_radius": 0.02},
                on_frame=stop)
    # Interrupted like a Ctrl-C: a checkpoint to resume from, no frames after it.
    assert (tmp_path / "checkpoint.pbfck").is_file()
    assert not (tmp_path / "frame_00003.ply").exists()
    resumed = pbf.run(dam_break, out=tmp_path, frames=3, overrides={"particle_radius": 0.02},
                      resume=True)
    assert resumed.resumed_from_frame is not None and resumed.frames == 3


def test_run_validates_its_arguments(dam_break, tmp_path):
    with pytest.raises(ValueError, match="frames"):
        pbf.run(dam_break, out=tmp_path, frames=0)
    with pytest.raises(ValueError, match="device"):
        pbf.run(dam_break, out=tmp_path, frames=1, device="gpu")
    with pytest.raises(pbf.IoError, match="cannot create output directory"):
        (tmp_path / "file").write_text("x")
        pbf.run(dam_break, out=tmp_path / "file" / "sub", frames=1,
                overrides={"particle_radius": 0.02})


def test_the_summary_balances_the_water_of_an_open_channel(scenes_dir, tmp_path):
    out = tmp_path / "channel"
    summary = pbf.run(scenes_dir / "open_channel.json", out=out, frames=75)
    assert summary.removed > 0  # the water reached the outlet
    assert summary.particles == 1880 + summary.emitted - summary.removed
    on_disk = json.loads((out / "summary.json").read_text())
    assert on_disk["emitted_particles"] == summary.emitted
    assert on_disk["removed_particles"] == summary.removed
    assert summary.as_dict()["removed"] == summary.removed
    rows = (out / "stats.csv").read_text().splitlines()
    header = rows[0].split(",")
    removed = sum(int(r.split(",")[header.index("removed")]) for r in rows[1:])
    assert removed == summary.removed
