"""world.positions / velocities / densities / ids are views of the World's
id-ordered buffers, not copies."""

import gc

import numpy as np
import pytest

import pbf


def test_views_share_the_worlds_buffers(small_world):
    w = small_world
    x, v, rho, ids = w.positions, w.velocities, w.densities, w.ids
    n = w.particle_count
    assert x.shape == (n, 3) and x.dtype == np.float32
    assert v.shape == (n, 3) and v.dtype == np.float32
    assert rho.shape == (n,) and rho.dtype == np.float32
    assert ids.shape == (n,) and ids.dtype == np.uint64
    assert np.array_equal(ids, np.arange(n))
    assert np.shares_memory(x, w.positions)  # a second access gives the same memory
    before = x.copy()
    w.step_frame()
    # The same array object now holds the new state (updated in place).
    assert not np.array_equal(before, x)
    assert np.array_equal(x, w.positions)
    assert np.abs(v).max() > 0


def test_writing_a_position_moves_the_particle(small_world):
    w = small_world
    x = w.positions
    top = int(np.argmax(x[:, 1]))  # a particle on the top of the column
    y0 = float(x[top, 1])
    x[top, 1] += 0.2  # lift it 20 cm through the view
    w.step_frame()
    # It fell freely from the new height for one frame (1/30 s):
    # y = y0 + 0.2 - g t^2 / 2 = y0 + 0.1945; had the write been lost it
    # would be at or below y0.
    assert w.positions[top, 1] == pytest.approx(y0 + 0.2 - 0.5 * 9.81 / 30**2, abs=2e-3)


def test_writing_a_velocity_moves_the_particle(small_world):
    w = small_world
    top = int(np.argmax(w.positions[:, 1]))
    x0 = w.positions[top].copy()
    w.velocities[top] = (0.0, 3.0, 0.0)  # thrown up at 3 m/s
    w.step_frame()
    rise = w.positions[top, 1] - x0[1]
    t = 1 / 30
    assert rise == pytest.approx(3.0 * t - 0.5 * 9.81 * t * t, abs=0.01)
    assert w.velocities[top, 1] == pytest.approx(3.0 - 9.81 * t, abs=0.05)


def test_densities_and_ids_are_read_only(small_world):
    w = small_world
    with pytest.raises(ValueError, match="read-only"):
        w.densities[0] = 1.0
    with pytest.raises(ValueError, match="read-only"):
        w.ids[0] = 7
    assert w.densities.base is not None and w.ids.base is not None


def test_a_view_outlives_its_world(dam_break):
    w = pbf.World.from_scene(dam_break, {"particle_radius": 0.02})
    x = w.positions
    expected = x.copy()
    del w
    gc.collect()
    # The capsule that is the array's base keeps the buffer alive.
    assert np.array_equal(x, expected)
    x[0] = (1.0, 2.0, 3.0)
    assert x[0, 2] == 3.0


def test_views_follow_a_changed_particle_count(small_world):
    w = small_world
    old = w.positions
    n = w.particle_count
    w.add_particles([[1.0, 0.5, 0.2]])
    assert old.shape == (n, 3)  # the old view is detached but valid
    assert w.positions.shape == (n + 1, 3)
    assert not np.shares_memory(old, w.positions)
