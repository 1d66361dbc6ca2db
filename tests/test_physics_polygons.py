"""Polygons, capsules and segments in a world, against known answers: resting heights,
a friction stopping distance, sliding and sticking on a slope, an impulse's spin from the
geometry's moment, a nearly round polygon rolling as its inertia says, a bounce's ratio,
momentum in a free scene, energy readouts, and a stack that stays put."""

from __future__ import annotations

import math

import numpy as np
import pytest

import impulse2d as p2
from impulse2d import geometry

G = 9.81
DT = 1 / 60


def hexagon(r: float = 0.5) -> list[tuple[float, float]]:
    """A regular hexagon of circumradius ``r`` with a flat bottom edge."""
    return [(r * math.cos(t), r * math.sin(t)) for t in np.arange(6) * np.pi / 3]


def run(world: p2.World, seconds: float, dt: float = DT) -> None:
    world.step(dt, round(seconds / dt))


def test_outlines_come_to_rest_on_the_ground_at_their_own_heights():
    """A triangle on its base rests with its centroid at a third of its height, a capsule
    lying down at its radius, a hexagon on an edge at its inner radius, a rounded square
    at half its side plus the rounding; all within 1 mm, and all asleep."""
    world = p2.World()
    world.add(p2.Plane())
    tri = world.add(p2.Polygon(vertices=[(0, 0), (1, 0), (0.5, 0.9)], position=(-3, 1.0)))
    cap = world.add(p2.Capsule(length=1.0, radius=0.2, position=(-1, 0.5)))
    hexa = world.add(p2.Polygon(vertices=hexagon(0.5), position=(1, 1.0)))
    rounded = world.add(
        p2.Polygon(vertices=[(0.3, 0.3), (-0.3, 0.3), (-0.3, -0.3), (0.3, -0.3)], radius=0.05,
                   position=(3, 1.0))
    )  # fmt: skip
    run(world, 4.0)
    expected = {tri: 0.3, cap: 0.2, hexa: 0.5 * math.sqrt(3) / 2, rounded: 0.35}
    for body, height in expected.items():
        assert body.position[1] == pytest.approx(height, abs=1e-3)
        assert abs(body.angle) < 1e-3
        assert not body.awake


@pytest.mark.parametrize("make", ["square", "triangle", "capsule"])
def test_friction_stops_a_sliding_outline_in_v0_squared_over_2_mu_g(make):
    """Pushed along flat ground at 3 m/s with friction 0.4, any flat-bottomed outline
    slides ``v0^2 / (2 mu g)`` = 1.147 m before it stops (2 %)."""
    world = p2.World(substeps=8)
    world.add(p2.Plane(friction=0.4))
    shapes = {
        "square": lambda: p2.Polygon(vertices=[(0.25, 0.25), (-0.25, 0.25), (-0.25, -0.25),
                                               (0.25, -0.25)], position=(0, 0.25)),
        "triangle": lambda: p2.Polygon.placed([(-0.4, 0.0), (0.4, 0.0), (0.0, 0.3)]),
        "capsule": lambda: p2.Capsule(length=0.6, radius=0.1, position=(0, 0.1)),
    }  # fmt: skip
    body = world.add(shapes[make]())
    body.friction = 0.4
    run(world, 0.5)  # settle onto the ground
    start = float(body.position[0])
    body.velocity = (3.0, 0.0)
    run(world, 2.0)
    assert float(body.position[0]) - start == pytest.approx(9.0 / (2 * 0.4 * G), rel=0.02)
    assert abs(float(body.velocity[0])) < 1e-3


def _slope(world: p2.World, degrees: float, friction: float) -> np.ndarray:
    theta = math.radians(degrees)
    normal = np.array([-math.sin(theta), math.cos(theta)])
    world.add(p2.Plane(normal=normal, friction=friction))
    return np.array([math.cos(theta), math.sin(theta)])  # down the slope is -this


@pytest.mark.parametrize(("friction", "slides"), [(0.2, True), (0.6, False)])
def test_a_block_on_a_30_degree_slope_slides_as_its_friction_says(friction, slides):
    """On a 30 degree slope (tan 30 = 0.577) a square polygon with friction 0.6 stays put;
    with 0.2 it slides ``g (sin - mu cos) t^2 / 2`` down it in 1 s (3 %)."""
    world = p2.World(substeps=8)
    along = _slope(world, 30.0, friction)
    theta = math.radians(30.0)
    normal = np.array([-along[1], along[0]])
    block = world.add(
        p2.Polygon(vertices=[(0.2, 0.2), (-0.2, 0.2), (-0.2, -0.2), (0.2, -0.2)],
                   position=tuple(0.2 * normal), angle=theta, friction=friction)
    )  # fmt: skip
    start = np.array(block.position)
    run(world, 1.0)
    travelled = -float((np.array(block.position) - start) @ along)
    if slides:
        expected = 0.5 * G * (math.sin(theta) - friction * math.cos(theta)) * 1.0**2
        assert travelled == pytest.approx(expected, rel=0.03)
    else:
        assert abs(travelled) < 2e-3


def test_an_impulse_off_centre_spins_a_polygon_by_its_geometric_moment():
    """An impulse J at r from the centre of mass of a free triangle: v = J / m and
    omega = (r x J) / I, with I the mass times ``geometry.mass``'s moment per area."""
    world = p2.World(gravity=(0.0, 0.0))
    vertices = [(0.0, 0.0), (1.2, 0.0), (0.3, 0.8)]
    tri = world.add(p2.Polygon.placed(vertices, mass=2.5))
    props = geometry.mass(vertices)
    moment = 2.5 * props.moment / props.area
    assert tri.moment == pytest.approx(moment, rel=1e-12)
    r, impulse = np.array([0.2, -0.1]), np.array([0.0, 1.5])
    tri.apply_impulse(impulse, point=np.array(tri.position) + r)
    np.testing.assert_allclose(tri.velocity, impulse / 2.5, rtol=1e-12)
    assert tri.angular_velocity == pytest.approx((r[0] * impulse[1] - r[1] * impulse[0]) / moment)


def test_a_nearly_round_polygon_rolls_down_a_slope_as_a_disc():
    """A small triangle rounded by 0.5 m is nearly a disc (I close to m r^2 / 2): on a 15
    degree slope with friction 1 it rolls without slipping, its centre gaining speed at
    ``g sin / (1 + I / (m R^2))`` (about 2/3 g sin), not g sin (4 %)."""
    world = p2.World(substeps=8)
    along = _slope(world, 15.0, 1.0)
    normal = np.array([-along[1], along[0]])
    core = [(0.01, 0.0), (-0.005, 0.0087), (-0.005, -0.0087)]
    ball = world.add(p2.Polygon(vertices=core, radius=0.5, position=tuple(0.52 * normal),
                                friction=1.0))  # fmt: skip
    run(world, 0.3)
    v0 = float(np.array(ball.velocity) @ -along)
    run(world, 1.0)
    gained = float(np.array(ball.velocity) @ -along) - v0
    reach = 0.5 + 0.0058  # the rounding plus the core's inner radius, about
    unit = ball.moment / ball.mass
    expected = G * math.sin(math.radians(15.0)) / (1.0 + unit / reach**2)
    assert gained == pytest.approx(expected, rel=0.04)
    # Rolling to the left (down this slope): counter-clockwise, at the speed over R.
    assert float(ball.angular_velocity) == pytest.approx(
        float(np.array(ball.velocity) @ -along) / reach, rel=0.04
    )


def test_a_flat_landing_bounces_with_the_restitution_ratio():
    """A square polygon dropped flat with restitution 0.5 leaves the ground at half the
    speed it arrived with (5 %), without turning."""
    world = p2.World(substeps=8)
    world.add(p2.Plane(restitution=0.5))
    block = world.add(
        p2.Polygon(vertices=[(0.3, 0.2), (-0.3, 0.2), (-0.3, -0.2), (0.3, -0.2)],
                   position=(0, 1.2), restitution=0.5)
    )  # fmt: skip
    before = 0.0
    for _ in range(120):
        previous = float(block.velocity[1])
        world.step(1 / 240)
        if previous < 0.0 <= float(block.velocity[1]):
            before = previous
            break
    after = float(block.velocity[1])
    assert before < -3.0
    assert after / -before == pytest.approx(0.5, rel=0.05)
    assert abs(float(block.angular_velocity)) < 1e-6


def test_a_free_scene_of_outlines_keeps_its_momentum():
    """Polygons and capsules thrown together without gravity or planes: total linear
    momentum is kept to rounding, and with restitution 0 so is angular momentum about
    the origin (1e-9 of the scale)."""
    world = p2.World(gravity=(0.0, 0.0), sleeping=False)
    rng = np.random.default_rng(7)
    bodies = []
    for k in range(6):
        position = (1.2 * (k % 3) - 1.2, 1.2 * (k // 3) - 0.6)
        velocity = tuple(rng.uniform(-2, 2, 2))
        if k % 2:
            body = p2.Capsule(
                length=0.5,
                radius=0.2,
                position=position,
                velocity=velocity,
                mass=float(rng.uniform(0.5, 2)),
                angle=float(rng.uniform(0, 3)),
            )
        else:
            body = p2.Polygon(
                vertices=hexagon(0.4),
                position=position,
                velocity=velocity,
                mass=float(rng.uniform(0.5, 2)),
                angular_velocity=3.0,
            )
        bodies.append(world.add(body))  # fmt: skip

    def momenta():
        linear = sum(b.mass * np.array(b.velocity) for b in bodies)
        angular = sum(
            b.moment * b.angular_velocity
            + b.mass * (b.position[0] * b.velocity[1] - b.position[1] * b.velocity[0])
            for b in bodies
        )
        return linear, angular

    linear0, angular0 = momenta()
    touched = 0
    for _ in range(180):
        world.step(DT)
        touched += len(world.contacts().slot_a) > 0
    linear, angular = momenta()
    assert touched > 10
    np.testing.assert_allclose(linear, linear0, atol=1e-9)
    assert angular == pytest.approx(angular0, abs=1e-9)


def test_energy_readouts_count_a_polygons_motion_and_height():
    """A spinning, moving polygon's kinetic energy is m v^2 / 2 + I w^2 / 2, and its
    potential m g y; a fixed segment counts for nothing."""
    world = p2.World()
    world.add(p2.Segment(start=(-5, 0), end=(5, 0)))
    tri = world.add(p2.Polygon.placed([(0, 1), (1, 1), (0, 2)], mass=3.0, velocity=(1.0, 2.0),
                                      angular_velocity=4.0))  # fmt: skip
    energy = world.energy()
    assert energy.kinetic_linear == pytest.approx(0.5 * 3.0 * 5.0)
    assert energy.kinetic_rotational == pytest.approx(0.5 * tri.moment * 16.0)
    assert energy.potential == pytest.approx(3.0 * G * tri.position[1])


def test_a_stack_of_square_polygons_rests_as_the_same_stack_of_boxes():
    """Five 0.5 m square polygons stacked on the ground rest where five boxes do (the
    soft contacts' sag under the load above, 1.4 mm a contact at the bottom; 1e-6), the
    top less than 1 mm off the axis and within 1 cm of its nominal height, all asleep."""
    heights = {}
    for make in ("polygon", "box"):
        world = p2.World(substeps=4)
        world.add(p2.Plane())
        square = [(0.25, 0.25), (-0.25, 0.25), (-0.25, -0.25), (0.25, -0.25)]
        bodies = []
        for k in range(5):
            at = (0.0, 0.25 + 0.5 * k)
            body = (
                p2.Polygon(vertices=square, position=at)
                if make == "polygon"
                else (p2.Box(width=0.5, height=0.5, position=at))
            )
            bodies.append(world.add(body))  # fmt: skip
        run(world, 5.0)
        assert not any(b.awake for b in bodies)
        assert abs(float(bodies[-1].position[0])) < 1e-3
        heights[make] = np.array([float(b.position[1]) for b in bodies])
    np.testing.assert_allclose(heights["polygon"], heights["box"], atol=1e-6)
    assert heights["polygon"][-1] == pytest.approx(2.25, abs=0.01)


def test_a_ball_rolls_down_a_segment_ramp_and_off_its_end():
    """A fixed segment as a ramp: a ball rolls down it (its speed along the ramp grows as
    a rolling disc's, 2/3 g sin t over 0.5 s, 3 %), then falls off the end."""
    world = p2.World(substeps=8)
    ramp = world.add(p2.Segment(start=(0, 2), end=(4, 0), friction=1.0))
    along = np.array([4.0, -2.0]) / math.hypot(4.0, 2.0)
    normal = np.array([-along[1], along[0]])
    start = np.array([0.5, 1.75]) + 0.3 * normal
    ball = world.add(p2.Circle(radius=0.3, position=tuple(start), friction=1.0))
    world.step(DT, 3)
    v0 = float(np.array(ball.velocity) @ along)
    world.step(DT, 30)
    sine = 2.0 / math.hypot(4.0, 2.0)
    assert float(np.array(ball.velocity) @ along) - v0 == pytest.approx(
        2 / 3 * G * sine * 0.5, rel=0.03
    )
    run(world, 2.0)
    assert float(ball.position[0]) > 4.0 and float(ball.position[1]) < 0.0
    assert ramp.is_inside((2.0, 1.0)) and not ramp.is_inside((2.0, 1.2))
