"""Rigid bodies from Python: defined in code, read back from a running world."""

import math

import pbf
import pytest


def _tank_with_cube(density):
    d = pbf.WorldDef(name="tank")
    d.simulation.domain = ((0, 0, 0), (0.4, 0.4, 0.3))
    d.simulation.particle_radius = 0.01
    d.fluid_blocks.append(pbf.FluidBlock((0, 0, 0), (0.4, 0.2, 0.3)))
    d.rigid_bodies.append(pbf.RigidBodyDescription(
        pbf.SolidDescription.box((0.15, 0.25, 0.1), (0.25, 0.35, 0.2)), density=density))
    return d


def test_body_falls_into_water_and_is_pushed_back():
    world = pbf.World(_tank_with_cube(500))
    [body] = world.bodies
    assert body.mass == pytest.approx(0.5)
    assert body.position == pytest.approx((0.2, 0.3, 0.15))
    assert body.orientation == pytest.approx((1, 0, 0, 0))
    for _ in range(12):
        world.step_frame()
    body = world.bodies[0]
    assert body.position[1] < 0.3           # it fell
    assert body.fluid_force[1] > 1.0        # and the water pushes it up (weight 4.9 N)
    assert world.report().statistics.inside_solid == 0
    assert world.solids[body.solid].startswith("box")


def test_set_body_state_moves_it():
    world = pbf.World(_tank_with_cube(500))
    world.set_body_state(0, position=(0.2, 0.32, 0.15), velocity=(0, 1, 0))
    body = world.bodies[0]
    assert body.position == pytest.approx((0.2, 0.32, 0.15))
    assert body.velocity == pytest.approx((0, 1, 0))
    with pytest.raises(IndexError):
        world.set_body_state(3, velocity=(0, 0, 0))


def test_bad_density_names_the_field():
    d = _tank_with_cube(-1)
    with pytest.raises(pbf.SceneError, match=r"rigid_bodies\[0\]\.density"):
        pbf.World(d)
