"""Shared fixtures. CTest runs this suite with PYTHONPATH pointing at the
build tree's module and PBF_CLI / PBF_SCENES_DIR set (python/CMakeLists.txt);
run by hand:
    PYTHONPATH=build/release/python python3 -m pytest -q python/tests
"""

import os
import pathlib

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def scenes_dir():
    return pathlib.Path(os.environ.get("PBF_SCENES_DIR", REPO / "scenes"))


@pytest.fixture(scope="session")
def dam_break(scenes_dir):
    return scenes_dir / "dam_break.json"


@pytest.fixture(scope="session")
def cli():
    """The `pbf` binary the Python results are compared with."""
    path = pathlib.Path(os.environ.get("PBF_CLI", REPO / "build" / "release" / "pbf"))
    if not path.is_file():
        pytest.fail(f"pbf CLI not found at {path}: build the pbf_cli target or set PBF_CLI")
    return path


# The dam break at twice the particle radius: ~2,000 particles, a frame in
# well under 0.1 s, the same physics as the shipped scene.
SMALL = {"particle_radius": 0.02}


@pytest.fixture
def small_world(dam_break):
    import pbf

    return pbf.World.from_scene(dam_break, SMALL)


def require_device(device):
    """Skips when `device` cannot run here (a build without it, or no GPU:
    pbf.World raises RuntimeError "device cuda: ..." then), with the reason."""
    import pbf

    probe = pbf.WorldDef(name="probe")
    probe.fluid_blocks.append(pbf.FluidBlock((0, 0, 0), (0.1, 0.1, 0.1)))
    try:
        pbf.World(probe, device=device)
    except RuntimeError as error:
        if str(error).startswith(f"device {device}: "):
            pytest.skip(str(error))
        raise
