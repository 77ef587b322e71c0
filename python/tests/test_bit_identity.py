"""A frame stepped from Python is the frame `pbf run` writes, to the bit:
the module drives the same World and frame loop as the CLI, and reading
and writing back the id-ordered arrays (which happens at every step once a
script has looked at them) changes no bit."""

import subprocess

import numpy as np
import pytest

import pbf
from conftest import require_device

FRAMES = 3


def cli_frames(cli, scene, overrides, out, device):
    command = [str(cli), "run", str(scene), "--frames", str(FRAMES), "--threads", "1",
               "--out", str(out), "--quiet", "--device", device]
    for o in overrides:
        command += ["--set", o]
    subprocess.run(command, check=True, capture_output=True, text=True, timeout=600)
    return [pbf.read_ply(out / f"frame_{k:05d}.ply") for k in range(FRAMES + 1)]


def assert_same_bits(world, ply, frame):
    ids = world.ids
    assert np.array_equal(ply["id"], ids), f"frame {frame}: ids"
    # Byte-for-byte: compare the float32 bit patterns, not values (NaN-safe,
    # and -0.0 differs from 0.0).
    for name, columns in (("position", ("x", "y", "z")), ("velocity", ("vx", "vy", "vz"))):
        mine = world.positions if name == "position" else world.velocities
        theirs = np.stack([ply[c] for c in columns], axis=1).astype(np.float32)
        assert np.array_equal(mine.view(np.uint32), theirs.view(np.uint32)), \
            f"frame {frame}: {name} differs in {np.count_nonzero(mine != theirs)} values"
    assert np.array_equal(world.densities.view(np.uint32),
                          ply["density"].astype(np.float32).view(np.uint32)), \
        f"frame {frame}: density"


@pytest.mark.parametrize("device", ["cpu", "reference", "cuda-on-cpu", "cuda"])
def test_python_frames_equal_cli_frames(cli, dam_break, tmp_path, device):
    require_device(device)
    overrides = ["particle_radius=0.02"]
    frames = cli_frames(cli, dam_break, overrides, tmp_path / "cli", device)
    assert len(frames[0]) > 1000
    world = pbf.World.from_scene(dam_break, overrides, device=device)
    pbf.set_threads(2)  # the CLI ran with 1: results do not depend on the thread count
    assert_same_bits(world, frames[0], 0)
    for k in range(1, FRAMES + 1):
        world.step_frame()
        assert_same_bits(world, frames[k], k)


def test_read_ply_reads_the_cli_format(cli, dam_break, tmp_path):
    frame = cli_frames(cli, dam_break, ["particle_radius=0.02"], tmp_path, "cpu")[0]
    assert frame.dtype.names == ("x", "y", "z", "vx", "vy", "vz", "density", "id")
    assert frame.dtype.itemsize == 32
    assert frame["density"][0] == 1000.0 and np.array_equal(frame["id"], np.arange(len(frame)))
