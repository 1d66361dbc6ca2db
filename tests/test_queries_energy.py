"""Queries and energy readouts against analytic geometry and hand-computed values."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import impulse2d as p2

coord = st.floats(-10.0, 10.0, allow_nan=False, allow_infinity=False)
size = st.floats(0.05, 5.0, allow_nan=False, allow_infinity=False)
angle = st.floats(-2.0 * math.pi, 2.0 * math.pi, allow_nan=False, allow_infinity=False)
EPS = 1e-9  # points this close to a boundary are left out: either answer is right there


# -- analytic geometry, written independently of the engine ----------------------------------------
def in_circle(centre, radius, point) -> tuple[bool, float]:
    """Inside test and distance of ``point`` from the circle's edge."""
    d = math.hypot(point[0] - centre[0], point[1] - centre[1])
    return bool(d <= radius), abs(d - radius)


def box_corners(centre, width, height, theta) -> np.ndarray:
    """Corners of a rotated box, counter-clockwise."""
    c, s = math.cos(theta), math.sin(theta)
    local = [
        (-width / 2, -height / 2),
        (width / 2, -height / 2),
        (width / 2, height / 2),
        (-width / 2, height / 2),
    ]
    return np.array([(centre[0] + c * x - s * y, centre[1] + s * x + c * y) for x, y in local])


def in_polygon(corners: np.ndarray, point) -> tuple[bool, float]:
    """Inside test for a convex counter-clockwise polygon by edge cross products, and the
    distance from the nearest edge line."""
    margins = []
    for i in range(len(corners)):
        a, b = corners[i], corners[(i + 1) % len(corners)]
        edge = b - a
        cross = edge[0] * (point[1] - a[1]) - edge[1] * (point[0] - a[0])
        margins.append(cross / math.hypot(*edge))  # signed distance, > 0 inside
    return bool(min(margins) >= 0.0), float(min(abs(m) for m in margins))


# -- is_inside -------------------------------------------------------------------------------
@settings(max_examples=200, deadline=None)
@given(cx=coord, cy=coord, radius=size, theta=angle, px=coord, py=coord)
def test_circle_is_inside_matches_geometry(cx, cy, radius, theta, px, py):
    """Circle.is_inside agrees with |p - c| <= r for random circles and points."""
    inside, gap = in_circle((cx, cy), radius, (px, py))
    assume(gap > EPS)
    world = p2.World()
    c = world.add(p2.Circle(position=(cx, cy), radius=radius, angle=theta))
    assert c.is_inside((px, py)) is inside


@settings(max_examples=200, deadline=None)
@given(cx=coord, cy=coord, w=size, h=size, theta=angle, u=st.floats(-1.5, 1.5), v=coord)
def test_rotated_box_is_inside_matches_geometry(cx, cy, w, h, theta, u, v):
    """Box.is_inside agrees with the rotated rectangle's edge tests for random boxes/points."""
    # Half the points are drawn near the box (u scales the box diagonal), half anywhere.
    reach = math.hypot(w, h)
    point = (cx + u * reach, cy + (v / 10.0) * reach) if abs(v) < 5.0 else (u * 6.0, v)
    inside, gap = in_polygon(box_corners((cx, cy), w, h, theta), point)
    assume(gap > EPS)
    world = p2.World()
    box = world.add(p2.Box(position=(cx, cy), width=w, height=h, angle=theta))
    assert box.is_inside(point) is inside


@settings(max_examples=200, deadline=None)
@given(
    nx=st.floats(-3.0, 3.0),
    ny=st.floats(-3.0, 3.0),
    qx=coord,
    qy=coord,
    px=coord,
    py=coord,
)
def test_plane_is_inside_matches_half_space(nx, ny, qx, qy, px, py):
    """Plane.is_inside is True exactly in the solid half-space behind the normal."""
    length = math.hypot(nx, ny)
    assume(length > 1e-3)
    depth = ((px - qx) * nx + (py - qy) * ny) / length
    assume(abs(depth) > EPS)
    plane = p2.Plane(normal=(nx, ny), point=(qx, qy))
    world = p2.World()
    world.add(plane)
    assert plane.is_inside((px, py)) is (depth < 0.0)


def test_is_inside_known_points():
    """Hand-picked points inside and outside a circle, a 45-degree box and a ground plane."""
    world = p2.World()
    c = world.add(p2.Circle(position=(0.0, 5.0), radius=0.5))
    b = world.add(p2.Box(position=(2.0, 0.0), width=2.0, height=2.0, angle=math.pi / 4))
    g = world.add(p2.Plane(normal=(0.0, 1.0), point=(0.0, -1.0)))
    assert c.is_inside((0.1, 5.0)) and not c.is_inside((0.4, 5.4))
    assert b.is_inside((2.0, 1.35)) and not b.is_inside((2.9, 0.9))  # corner points up
    assert g.is_inside((100.0, -1.5)) and g.is_inside((0.0, -1.0)) and not g.is_inside((0, -0.9))


def test_is_inside_in_a_batch():
    """In a batch, is_inside gives one bool per world, using that world's pose and size."""
    world = p2.World(batch_size=3)
    c = world.add(p2.Circle(radius=1.0))
    c.position = [[0.0, 0.0], [5.0, 0.0], [0.0, 0.0]]
    c.radius = [1.0, 1.0, 0.2]
    result = c.is_inside((0.5, 0.0))
    assert np.shape(result) == (3,)
    np.testing.assert_array_equal(result, [True, False, False])
    b = world.add(p2.Box(width=2.0, height=0.2))
    b.angle = [0.0, math.pi / 2, math.pi]
    np.testing.assert_array_equal(b.is_inside((0.9, 0.0)), [True, False, True])


# -- query_point ---------------------------------------------------------------------------------
def query_scene(world: p2.World) -> list:
    """Overlapping circles and boxes (dynamic, fixed, kinematic) plus two planes."""
    return [
        world.add(p2.Plane(normal=(0.0, 1.0), point=(0.0, -2.0))),
        world.add(p2.Circle(position=(0.0, 0.0), radius=1.0)),
        world.add(p2.Box(position=(0.8, 0.3), width=2.0, height=0.6, angle=0.4)),
        world.add(p2.Circle(position=(1.5, 0.5), radius=0.7, fixed=True)),
        world.add(p2.Box(position=(-1.0, -0.5), width=1.0, height=3.0, angle=-0.7, kinematic=True)),
        world.add(p2.Plane(normal=(-1.0, 0.2), point=(2.5, 0.0))),
        world.add(p2.Box(position=(0.2, -0.2), width=0.5, height=0.5, fixed=True)),
    ]


def expected_hits(objects: list, point) -> list | None:
    """Bodies containing ``point`` by analytic geometry, or None if it is on a boundary."""
    hits = []
    for obj in objects:
        if isinstance(obj, p2.Plane):
            continue
        if isinstance(obj, p2.Circle):
            inside, gap = in_circle(obj.position, obj.radius, point)
        else:
            corners = box_corners(obj.position, obj.width, obj.height, obj.angle)
            inside, gap = in_polygon(corners, point)
        if gap <= EPS:
            return None
        if inside:
            hits.append(obj)
    return hits


@settings(max_examples=200, deadline=None)
@given(px=st.floats(-3.0, 3.0), py=st.floats(-3.0, 3.0))
def test_query_point_returns_exactly_the_containing_bodies(px, py):
    """query_point returns exactly the circles/boxes containing the point, in slot order."""
    world = p2.World()
    objects = query_scene(world)
    expected = expected_hits(objects, (px, py))
    assume(expected is not None)
    found = world.query_point((px, py))
    assert isinstance(found, list)
    assert not any(isinstance(obj, p2.Plane) for obj in found)
    assert found == expected


def test_query_point_known_points():
    """Points in several overlapping bodies, in one, and only inside planes."""
    world = p2.World()
    plane, circle, box, fixed_circle, kin_box, _, small = query_scene(world)
    assert world.query_point((0.2, -0.2)) == [circle, box, small]
    assert world.query_point((1.8, 0.9)) == [fixed_circle]
    assert world.query_point((-1.77, -1.42)) == [kin_box]
    assert world.query_point((0.0, -5.0)) == []  # inside the ground plane only
    assert plane.is_inside((0.0, -5.0))
    assert world.query_point((0.0, 10.0)) == []


def test_query_point_in_a_batch_uses_the_given_world():
    """query_point(point, world=k) looks at world k only, and skips bodies disabled there."""
    world = p2.World(batch_size=3)
    a = world.add(p2.Circle(radius=0.5))
    b = world.add(p2.Box(position=(0.0, 0.0), width=1.0, height=1.0))
    a.position = [[0.0, 0.0], [3.0, 0.0], [0.0, 0.0]]
    b.enabled = np.array([True, True, False])
    assert world.query_point((0.1, 0.1), world=0) == [a, b]
    assert world.query_point((0.1, 0.1), world=1) == [b]
    assert world.query_point((0.1, 0.1), world=2) == [a]
    assert world.query_point((3.1, 0.0), world=1) == [a]
    assert world.query_point((0.1, 0.1)) == [a, b]  # world 0 by default


# -- energy ----------------------------------------------------------------------------------------
def energy_scene(world: p2.World) -> tuple:
    world.gravity = (0.5, -9.81)
    circle = world.add(
        p2.Circle(
            position=(1.0, 3.0), radius=0.5, mass=2.0, velocity=(3.0, -4.0), angular_velocity=2.0
        )
    )
    box = world.add(
        p2.Box(
            position=(-2.0, 1.0),
            width=1.0,
            height=2.0,
            mass=3.0,
            angle=0.3,
            velocity=(1.0, 0.0),
            angular_velocity=-1.0,
        )
    )
    world.add(p2.Plane(point=(0.0, -5.0)))
    spring = world.add(
        p2.Spring(
            circle, box, rest_length=1.0, stiffness=10.0, anchor1=(0.5, 0.0), anchor2=(0.5, 1.0)
        )
    )
    return circle, box, spring


def hand_elastic() -> float:
    """k (L - L0)^2 / 2 for the spring of ``energy_scene``, computed by hand."""
    end1 = (1.0 + 0.5, 3.0)
    c, s = math.cos(0.3), math.sin(0.3)
    end2 = (-2.0 + 0.5 * c - 1.0 * s, 1.0 + 0.5 * s + 1.0 * c)
    length = math.hypot(end2[0] - end1[0], end2[1] - end1[1])
    return 0.5 * 10.0 * (length - 1.0) ** 2


# Hand-computed for energy_scene:
#   linear      = 2 (9 + 16) / 2 + 3 (1) / 2                         = 26.5
#   rotational  = (2 * 0.25 / 2) 4 / 2 + (3 (1 + 4) / 12) 1 / 2     = 0.5 + 0.625 = 1.125
#   potential   = -[2 (0.5 * 1 - 9.81 * 3) + 3 (0.5 * -2 - 9.81 * 1)] = 57.86 + 32.43 = 90.29
HAND = {"kinetic_linear": 26.5, "kinetic_rotational": 1.125, "potential": 90.29}


def test_energy_readouts_match_hand_computation():
    """energy() fields match m v^2/2, I w^2/2, -m g.p, k(L-L0)^2/2 computed by hand."""
    world = p2.World()
    energy_scene(world)
    e = world.energy()
    for name, value in HAND.items():
        assert getattr(e, name) == pytest.approx(value, rel=1e-12), name
    assert e.elastic == pytest.approx(hand_elastic(), rel=1e-12)
    assert hand_elastic() > 1.0  # the spring is really stretched
    assert e.kinetic == pytest.approx(26.5 + 1.125, rel=1e-12)
    assert e.total == pytest.approx(26.5 + 1.125 + 90.29 + hand_elastic(), rel=1e-12)
    for name in (
        "kinetic_linear",
        "kinetic_rotational",
        "potential",
        "elastic",
        "kinetic",
        "total",
    ):
        assert isinstance(getattr(e, name), float), name


def test_energy_follows_the_state():
    """energy() reads the current state: changing velocity, position and spring changes it."""
    world = p2.World()
    circle, box, spring = energy_scene(world)
    circle.velocity = (0.0, 0.0)
    circle.angular_velocity = 0.0
    box.position = (-2.0, 11.0)
    spring.stiffness = 0.0
    e = world.energy()
    assert e.kinetic_linear == pytest.approx(1.5, rel=1e-12)
    assert e.kinetic_rotational == pytest.approx(0.625, rel=1e-12)
    assert e.potential == pytest.approx(57.86 + 3.0 * (1.0 + 9.81 * 11.0), rel=1e-12)
    assert e.elastic == 0.0
    world.gravity = (0.0, 0.0)
    assert world.energy().potential == 0.0


def test_energy_leaves_out_fixed_and_kinematic_bodies():
    """Fixed and kinematic bodies are driven, not part of the system: they add no energy."""
    world = p2.World()
    world.add(p2.Box(position=(0.0, 10.0), mass=5.0, fixed=True))
    world.add(
        p2.Box(
            position=(3.0, 10.0),
            mass=5.0,
            velocity=(2.0, 0.0),
            angular_velocity=1.0,
            kinematic=True,
        )
    )
    world.add(p2.Plane())
    e = world.energy()
    assert (e.kinetic_linear, e.kinetic_rotational, e.potential, e.elastic) == (0, 0, 0, 0)


def test_energy_in_a_batch_is_per_world():
    """In a batch every energy field is an array of shape (B,), each world's own energy."""
    count = 3
    world = p2.World(batch_size=count)
    circle, box, spring = energy_scene(world)
    circle.velocity = [[3.0, -4.0], [0.0, 0.0], [6.0, 8.0]]
    spring.stiffness = [10.0, 0.0, 20.0]
    box.position = [[-2.0, 1.0], [-2.0, 1.0], [-2.0, 2.0]]
    box.enabled = np.array([True, True, False])
    e = world.energy()
    for name in (
        "kinetic_linear",
        "kinetic_rotational",
        "potential",
        "elastic",
        "kinetic",
        "total",
    ):
        assert np.shape(getattr(e, name)) == (count,), name
    box_linear, box_potential = 1.5, 32.43
    np.testing.assert_allclose(e.kinetic_linear, [26.5, box_linear, 100.0], rtol=1e-12)
    np.testing.assert_allclose(e.kinetic_rotational, [1.125, 1.125, 0.5], rtol=1e-12)
    np.testing.assert_allclose(e.potential, [90.29, 90.29, 90.29 - box_potential], rtol=1e-12)
    # World 2's box is disabled: no box energy and no spring there.
    np.testing.assert_allclose(e.elastic, [hand_elastic(), 0.0, 0.0], rtol=1e-12, atol=0)
    np.testing.assert_allclose(e.kinetic, e.kinetic_linear + e.kinetic_rotational, rtol=1e-15)
    np.testing.assert_allclose(
        e.total, e.kinetic_linear + e.kinetic_rotational + e.potential + e.elastic, rtol=1e-15
    )


def test_energy_of_a_batch_matches_single_worlds():
    """Each world's energy in a batch equals the energy of a single world in the same state."""
    batch = p2.World(batch_size=2)
    energy_scene(batch)
    batch.bodies[0].velocity = [[1.0, 2.0], [-3.0, 0.5]]
    for _ in range(30):
        batch.step(1.0 / 60.0)
    e = batch.energy()
    for k, velocity in enumerate([(1.0, 2.0), (-3.0, 0.5)]):
        single = p2.World()
        energy_scene(single)
        single.bodies[0].velocity = velocity
        for _ in range(30):
            single.step(1.0 / 60.0)
        s = single.energy()
        for name in ("kinetic_linear", "kinetic_rotational", "potential", "elastic"):
            assert getattr(e, name)[k] == getattr(s, name), (k, name)
