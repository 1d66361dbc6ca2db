"""The last contact stage alone (``projection.project_out_of_planes``): a body that a step
left deeper in a plane than half its smallest half size is moved out by the shortest
translation, to exactly that depth; nothing else moves, velocities are untouched. The
cases are hand-built: bodies placed deep in planes, their points found by the
narrowphase as in a step (``test_stage_solver.prepared``)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import impulse2d as p2
from impulse2d.core import projection
from impulse2d.core.state import OMEGA, VX
from test_stage_solver import prepared

ZERO_G = (0.0, 0.0)


def project(world: p2.World) -> np.ndarray:
    """Run the stage on world 0's points; returns the body rows before it."""
    step = prepared(world)
    before = step.body[0].copy()
    projection.project_out_of_planes(
        step.body, world.state.hull, world.layout.shapes, 0, step.points, step.ids, step.n
    )  # fmt: skip
    return before


def depth(world: p2.World, body, plane) -> float:
    slots = world.objects["bodies"]
    i, j = slots.index(body), slots.index(plane)
    state = world.state
    return projection.depth_in_plane(state.body, state.hull, world.layout.shapes, 0, i, j)


def test_a_disc_deep_in_the_ground_ends_exactly_half_its_radius_in():
    world = p2.World(gravity=ZERO_G)
    ground = world.add(p2.Plane(point=(0.0, 0.0)))
    ball = world.add(p2.Circle(position=(0.3, 0.1), radius=0.5, velocity=(1.0, -2.0)))
    before = project(world)
    assert depth(world, ball, ground) == pytest.approx(0.25, abs=1e-12)
    assert ball.position[0] == 0.3  # along the normal only
    assert ball.position[1] == pytest.approx(0.25, abs=1e-12)
    np.testing.assert_array_equal(world.state.body[0, :, VX : OMEGA + 1], before[:, VX : OMEGA + 1])


def test_a_tilted_box_moves_until_its_deepest_corner_is_at_the_allowance():
    """A 2 x 0.2 m box at 30 degrees: its support distance along the normal is
    1 sin 30 + 0.1 cos 30; the allowance is half of 0.1."""
    world = p2.World(gravity=ZERO_G)
    ground = world.add(p2.Plane(point=(0.0, 0.0)))
    box = world.add(p2.Box(position=(0.0, 0.2), width=2.0, height=0.2, angle=math.pi / 6))
    project(world)
    support = math.sin(math.pi / 6) + 0.1 * math.cos(math.pi / 6)
    assert box.position[1] == pytest.approx(support - 0.05, abs=1e-12)
    assert depth(world, box, ground) == pytest.approx(0.05, abs=1e-12)


def test_a_body_within_the_allowance_is_left_bitwise_alone():
    world = p2.World(gravity=ZERO_G)
    world.add(p2.Plane(point=(0.0, 0.0)))
    world.add(p2.Circle(position=(0.0, 0.26), radius=0.5))  # 0.24 in: allowed 0.25
    world.add(p2.Box(position=(3.0, 0.5), width=1.0, height=1.0))  # resting on it
    before = project(world)
    np.testing.assert_array_equal(world.state.body[0], before)


def test_in_a_corner_the_body_moves_out_of_both_planes_at_once():
    """A disc deep in the corner of a floor and a wall: moved along neither normal alone
    (each would push it into the other) but diagonally, to the allowance in both."""
    world = p2.World(gravity=ZERO_G)
    floor = world.add(p2.Plane(point=(0.0, 0.0)))
    wall = world.add(p2.Plane(normal=(1.0, 0.0), point=(0.0, 0.0)))
    ball = world.add(p2.Circle(position=(0.05, 0.1), radius=0.5))
    project(world)
    np.testing.assert_allclose(ball.position, (0.25, 0.25), atol=1e-12)
    assert depth(world, ball, floor) == pytest.approx(0.25, abs=1e-12)
    assert depth(world, ball, wall) == pytest.approx(0.25, abs=1e-12)


def test_in_a_wedge_the_move_is_the_corner_of_the_two_allowances():
    """Two planes at 90 +- 10 degrees from the floor meet above; a disc of radius 2.4 in
    the wedge, 2.4 - cos 10 deep in both (allowed 1.2), is moved down to where it is
    exactly at the allowance in each: by (2.4 - cos 10 - 1.2) / sin 10. Out of either
    plane alone it would go deeper into the other."""
    world = p2.World(gravity=ZERO_G)
    left = (math.cos(math.radians(10)), -math.sin(math.radians(10)))
    right = (-left[0], left[1])
    a = world.add(p2.Plane(normal=left, point=(-1.0, 0.0)))
    b = world.add(p2.Plane(normal=right, point=(1.0, 0.0)))
    ball = world.add(p2.Circle(position=(0.0, 0.0), radius=2.4))
    project(world)
    assert depth(world, ball, a) == pytest.approx(1.2, abs=1e-9)
    assert depth(world, ball, b) == pytest.approx(1.2, abs=1e-9)
    drop = (2.4 - math.cos(math.radians(10)) - 1.2) / math.sin(math.radians(10))
    np.testing.assert_allclose(ball.position, (0.0, -drop), atol=1e-9)


@pytest.mark.parametrize("motion", ["fixed", "kinematic"])
def test_fixed_and_kinematic_bodies_are_never_moved(motion):
    world = p2.World(gravity=ZERO_G)
    world.add(p2.Plane(point=(0.0, 0.0)))
    world.add(p2.Box(position=(0.0, 0.0), **{motion: True}))
    before = project(world)
    np.testing.assert_array_equal(world.state.body[0], before)
