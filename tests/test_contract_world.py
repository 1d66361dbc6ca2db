"""Public-contract tests, world: body kinds, material mixing, sleeping and batches.

These tests pin what a user of ``impulse2d`` relies on (fixed and kinematic bodies, the
mixing rules, sleeping, batches, a spring's default rest length, frames, ``replicate``,
``impulses`` and ``stop``), not how the engine computes it. Construction, properties,
setters, forces, impulses and removal are in ``test_contract_bodies.py``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import impulse2d as p2
from conftest import DT, G, resting_circle_world, steps


# -- helpers ---------------------------------------------------------------------------------------
def rebound_ratio(rule: str | None, e_ball: float, e_other: float, other: str) -> float:
    """Head-on hit in zero gravity: returned speed / approach speed along the line of impact."""
    kwargs = {} if rule is None else {"restitution_mixing": rule}
    world = p2.World(gravity=(0.0, 0.0), restitution_threshold=0.0, sleeping=False, **kwargs)
    ball = world.add(
        p2.Circle(
            position=(0.0, 0.0), radius=0.5, velocity=(2.0, 0.0), restitution=e_ball, friction=0.0
        )
    )
    if other == "ball":
        target = world.add(
            p2.Circle(
                position=(3.0, 0.0),
                radius=0.5,
                velocity=(-2.0, 0.0),
                restitution=e_other,
                friction=0.0,
            )
        )
        steps(world, 120)
        return float(target.velocity[0] - ball.velocity[0]) / 4.0
    if other == "cushion":
        world.add(
            p2.Box(
                position=(3.0, 0.0),
                width=1.0,
                height=4.0,
                fixed=True,
                restitution=e_other,
                friction=0.0,
            )
        )
    else:  # a plane facing the ball
        world.add(p2.Plane(normal=(-1.0, 0.0), point=(3.0, 0.0), restitution=e_other))
    steps(world, 120)
    return -float(ball.velocity[0]) / 2.0


# -- fixed and kinematic bodies --------------------------------------------------------------------
def test_fixed_body_never_moves():
    """A fixed body ignores gravity, forces, impulses and collisions: its pose never changes."""
    world = p2.World()
    post = world.add(
        p2.Box(position=(0.0, 1.0), width=1.0, height=2.0, angle=0.2, fixed=True, mass=5.0)
    )
    world.add(p2.Circle(position=(-3.0, 1.0), velocity=(8.0, 0.0), radius=0.4, mass=50.0))
    world.add(p2.Circle(position=(0.0, 4.0), radius=0.4, mass=50.0))
    assert post.fixed and not post.kinematic
    post.apply_force((1000.0, 1000.0), point=(0.5, 1.5))
    post.apply_impulse((100.0, 100.0), point=(0.5, 1.5))
    steps(world, 90)
    np.testing.assert_array_equal(post.position, [0.0, 1.0])
    assert post.angle == 0.2
    np.testing.assert_array_equal(post.velocity, [0.0, 0.0])
    assert post.angular_velocity == 0.0


def test_fixed_body_has_infinite_mass():
    """A very heavy ball rebounds from a fixed box exactly as from an immovable wall."""
    world = p2.World(gravity=(0.0, 0.0), restitution_threshold=0.0, sleeping=False)
    wall = world.add(
        p2.Box(
            position=(3.0, 0.0),
            width=1.0,
            height=4.0,
            fixed=True,
            restitution=1.0,
            friction=0.0,
            mass=1e-3,
        )
    )
    ball = world.add(p2.Circle(velocity=(3.0, 0.0), mass=1e6, restitution=1.0, friction=0.0))
    steps(world, 120)
    assert ball.velocity[0] == pytest.approx(-3.0, rel=1e-6)
    np.testing.assert_array_equal(wall.position, [3.0, 0.0])


def test_kinematic_body_moves_with_its_velocity_and_ignores_gravity():
    """A kinematic body moves with its given velocity, ignoring gravity and applied forces."""
    world = p2.World()
    k = world.add(
        p2.Box(position=(0.0, 1.0), velocity=(1.0, 0.5), angular_velocity=0.3, kinematic=True)
    )
    assert k.kinematic and not k.fixed
    for _ in range(60):
        k.apply_force((0.0, 100.0))
        world.step(DT)
    np.testing.assert_allclose(k.position, [1.0, 1.5], atol=1e-9)
    assert k.angle == pytest.approx(0.3, abs=1e-9)
    np.testing.assert_array_equal(k.velocity, [1.0, 0.5])
    assert k.angular_velocity == 0.3
    assert k.awake


def test_kinematic_body_pushes_dynamic_bodies_and_is_not_pushed_back():
    """A kinematic paddle pushes a dynamic ball and keeps its own velocity exactly."""
    world = p2.World(gravity=(0.0, 0.0))
    paddle = world.add(
        p2.Box(
            position=(0.0, 0.0),
            width=0.5,
            height=2.0,
            velocity=(2.0, 0.0),
            kinematic=True,
            mass=1e-3,
        )
    )
    ball = world.add(p2.Circle(position=(2.0, 0.0), radius=0.5, mass=100.0))
    steps(world, 90)
    np.testing.assert_array_equal(paddle.velocity, [2.0, 0.0])
    np.testing.assert_allclose(paddle.position, [3.0, 0.0], atol=1e-9)
    assert ball.velocity[0] >= 2.0 - 1e-6
    assert ball.position[0] > paddle.position[0] + 0.7


# -- material mixing -------------------------------------------------------------------------------
def test_default_restitution_mixing_is_max():
    """By default a contact bounces with the larger of the two restitutions."""
    assert rebound_ratio(None, 0.8, 0.0, "plane") == pytest.approx(0.8, abs=2e-3)
    assert rebound_ratio(None, 0.0, 0.6, "plane") == pytest.approx(0.6, abs=2e-3)
    assert rebound_ratio(None, 0.95, 0.75, "cushion") == pytest.approx(0.95, abs=2e-3)
    assert rebound_ratio(None, 0.9, 0.3, "ball") == pytest.approx(0.9, abs=2e-3)


def test_min_restitution_mixing_pool_table():
    """restitution_mixing='min': balls 0.95, cushion 0.75 give ball-ball 0.95, cushion 0.75."""
    assert rebound_ratio("min", 0.95, 0.95, "ball") == pytest.approx(0.95, abs=2e-3)
    assert rebound_ratio("min", 0.95, 0.75, "cushion") == pytest.approx(0.75, abs=2e-3)
    assert rebound_ratio("min", 0.95, 0.5, "ball") == pytest.approx(0.5, abs=2e-3)


def sliding_friction(mu_box: float, mu_plane: float, **world_kwargs) -> float:
    """Effective friction coefficient of a box sliding on a plane: deceleration / g."""
    world = p2.World(sleeping=False, **world_kwargs)
    world.add(p2.Plane(friction=mu_plane))
    box = world.add(p2.Box(position=(0.0, 0.5), width=1.0, height=1.0, friction=mu_box))
    steps(world, 30)
    box.velocity = (6.0, 0.0)
    steps(world, 30)
    return (6.0 - float(box.velocity[0])) / (0.5 * G)


def test_default_friction_mixing_is_sqrt():
    """By default a contact's friction is sqrt(a b) of the two coefficients."""
    assert sliding_friction(0.25, 1.0) == pytest.approx(0.5, abs=0.01)
    assert sliding_friction(1.0, 0.09) == pytest.approx(0.3, abs=0.01)


def test_friction_mixing_rule_is_honoured():
    """friction_mixing='min'/'max'/'mean'/'product' change the effective coefficient."""
    assert sliding_friction(0.25, 1.0, friction_mixing="min") == pytest.approx(0.25, abs=0.01)
    assert sliding_friction(0.25, 0.5, friction_mixing="max") == pytest.approx(0.5, abs=0.01)
    assert sliding_friction(0.25, 0.5, friction_mixing="mean") == pytest.approx(0.375, abs=0.01)
    assert sliding_friction(0.8, 0.5, friction_mixing="product") == pytest.approx(0.4, abs=0.01)


# -- sleeping --------------------------------------------------------------------------------------
def test_body_at_rest_falls_asleep_after_time_to_sleep():
    """A body resting on a plane is awake at 0.45 s and asleep by 0.7 s (time_to_sleep 0.5)."""
    world, ball = resting_circle_world()
    steps(world, 27)
    assert ball.awake
    steps(world, 15)
    assert not ball.awake
    np.testing.assert_array_equal(ball.velocity, [0.0, 0.0])
    y = ball.position[1]
    steps(world, 30)
    assert ball.position[1] == y and not ball.awake


def test_sleeping_disabled_keeps_bodies_awake():
    """World(sleeping=False) never puts a resting body to sleep."""
    world, ball = resting_circle_world(sleeping=False)
    steps(world, 90)
    assert ball.awake


def test_sleeping_body_wakes_when_hit():
    """A sleeping ball wakes when another body lands on it, and is pushed."""
    world, ball = resting_circle_world()
    dropped = world.add(p2.Circle(position=(0.3, 4.0), radius=0.5))
    steps(world, 36)
    assert not ball.awake, "precondition: asleep before the other ball arrives"
    assert dropped.position[1] > 2.0
    steps(world, 30)
    assert ball.awake
    assert abs(ball.position[0]) > 1e-3


def test_sleeping_stack_wakes_as_a_whole():
    """A sleeping stack of boxes wakes together when its bottom box is hit."""
    world = p2.World()
    world.add(p2.Plane())
    boxes = [world.add(p2.Box(position=(0.0, 0.5 + i), width=1.0, height=1.0)) for i in range(3)]
    steps(world, 90)
    assert not any(b.awake for b in boxes), "precondition: the stack sleeps"
    world.add(p2.Circle(position=(-3.0, 0.3), radius=0.3, velocity=(8.0, 0.0), mass=2.0))
    woke = None
    for i in range(40):
        world.step(DT)
        states = [b.awake for b in boxes]
        if any(states):
            assert all(states), "the stack must wake as a whole, not box by box"
            woke = i
            break
    assert woke is not None
    world.step(DT)
    assert boxes[0].velocity[0] > 0.1


# -- batches ---------------------------------------------------------------------------------------
def test_batch_property_shapes():
    """In World(batch_size=8) body properties return one value per world: (8,) or (8, 2)."""
    world = p2.World(batch_size=8)
    c = world.add(p2.Circle(position=(0.0, 5.0), radius=0.5))
    b = world.add(p2.Box(position=(2.0, 5.0), width=1.0, height=0.5))
    assert world.batch_size == 8
    for body in (c, b):
        assert body.position.shape == (8, 2) and body.velocity.shape == (8, 2)
        for name in (
            "angle",
            "angular_velocity",
            "mass",
            "moment",
            "restitution",
            "friction",
            "linear_drag",
            "angular_drag",
            "awake",
            "enabled",
        ):
            assert np.shape(getattr(body, name)) == (8,), name
    assert c.radius.shape == (8,) and b.width.shape == (8,) and b.height.shape == (8,)
    np.testing.assert_array_equal(c.position, np.tile([0.0, 5.0], (8, 1)))
    world.step(DT)
    assert np.shape(world.time) == (8,)
    np.testing.assert_allclose(world.time, DT)


def test_batch_setters_accept_one_value_or_one_per_world():
    """Batch setters broadcast a single value to all worlds or take one value per world."""
    world = p2.World(batch_size=4)
    c = world.add(p2.Circle())
    b = world.add(p2.Box(position=(3.0, 0.0)))
    c.position = (1.0, 2.0)
    np.testing.assert_array_equal(c.position, np.tile([1.0, 2.0], (4, 1)))
    per_world = np.arange(8.0).reshape(4, 2)
    c.velocity = per_world
    np.testing.assert_array_equal(c.velocity, per_world)
    c.radius = [0.1, 0.2, 0.3, 0.4]
    np.testing.assert_array_equal(c.radius, [0.1, 0.2, 0.3, 0.4])
    c.mass = 2.0
    np.testing.assert_allclose(c.moment, 0.5 * 2.0 * np.array([0.1, 0.2, 0.3, 0.4]) ** 2)
    b.width = np.array([1.0, 2.0, 3.0, 4.0])
    b.angle = 0.5
    np.testing.assert_array_equal(b.angle, np.full(4, 0.5))
    np.testing.assert_allclose(b.moment, (np.array([1.0, 4.0, 9.0, 16.0]) + 1.0) / 12.0)
    b.restitution = [0.0, 0.5, 1.0, 0.25]
    np.testing.assert_array_equal(b.restitution, [0.0, 0.5, 1.0, 0.25])
    c.enabled = np.array([True, False, True, False])
    np.testing.assert_array_equal(c.enabled, [True, False, True, False])
    c.enabled = True
    np.testing.assert_array_equal(c.enabled, [True] * 4)


def test_batch_apply_impulse_and_force_per_world():
    """apply_impulse and apply_force accept one vector for all worlds or one per world."""
    world = p2.World(batch_size=3, gravity=(0.0, 0.0))
    c = world.add(p2.Circle(mass=2.0))
    c.apply_impulse([[2.0, 0.0], [0.0, 2.0], [4.0, 4.0]])
    np.testing.assert_allclose(c.velocity, [[1.0, 0.0], [0.0, 1.0], [2.0, 2.0]])
    c.apply_force((2.0, 0.0))
    world.step(0.5)
    np.testing.assert_allclose(c.velocity, [[1.5, 0.0], [0.5, 1.0], [2.5, 2.0]], rtol=1e-12)


def test_spring_default_rest_length_is_anchor_distance():
    """A spring without rest_length takes the anchors' distance when added, and rests there."""
    world = p2.World(gravity=(0.0, 0.0))
    a = world.add(p2.Circle(position=(0.0, 0.0)))
    b = world.add(p2.Box(position=(3.0, 1.0), angle=0.5))
    s = world.add(p2.Spring(a, b, stiffness=10.0, anchor1=(0.2, 0.0), anchor2=(0.5, 0.0)))
    tip = np.array([3.0 + 0.5 * math.cos(0.5), 1.0 + 0.5 * math.sin(0.5)])
    expected = float(np.hypot(*(tip - [0.2, 0.0])))
    assert s.rest_length == pytest.approx(expected, rel=1e-12)
    assert s.length == pytest.approx(expected, rel=1e-12)
    steps(world, 10)
    np.testing.assert_allclose(a.velocity, [0.0, 0.0], atol=1e-12)


def test_spring_default_rest_length_in_a_batch():
    """In a batch, a spring without rest_length takes each world's anchor distance."""
    world = p2.World(batch_size=3, gravity=(0.0, 0.0))
    a = world.add(p2.Circle(position=(0.0, 0.0)))
    b = world.add(p2.Circle(position=(3.0, 0.0)))
    b.position = [[2.0, 0.0], [3.0, 0.0], [0.0, 4.0]]
    s = world.add(p2.Spring(a, b, stiffness=10.0))
    np.testing.assert_allclose(s.rest_length, [2.0, 3.0, 4.0], rtol=1e-12)
    np.testing.assert_allclose(s.length, [2.0, 3.0, 4.0], rtol=1e-12)


def test_spring_properties_are_settable():
    """Spring rest_length, stiffness, damping and anchors read back what was set and act."""
    world = p2.World(gravity=(0.0, 0.0))
    a = world.add(p2.Circle(position=(0.0, 0.0)))
    b = world.add(p2.Circle(position=(2.0, 0.0)))
    s = world.add(p2.Spring(a, b, rest_length=2.0, stiffness=50.0, damping=0.1))
    assert (s.body1, s.body2) == (a, b)
    world.step(DT)
    np.testing.assert_array_equal(b.velocity, [0.0, 0.0])  # at rest length: no force
    s.rest_length, s.stiffness, s.damping = 1.0, 20.0, 0.5
    s.anchor1, s.anchor2 = (0.1, 0.0), (-0.1, 0.0)
    assert (s.rest_length, s.stiffness, s.damping) == (1.0, 20.0, 0.5)
    np.testing.assert_array_equal(s.anchor1, [0.1, 0.0])
    np.testing.assert_array_equal(s.anchor2, [-0.1, 0.0])
    world.step(DT)
    assert a.velocity[0] > 0.0 and b.velocity[0] < 0.0


def test_to_world_and_to_local():
    """to_world rotates then translates a body-local point; to_local is its inverse."""
    world = p2.World()
    b = world.add(p2.Box(position=(1.0, 2.0), angle=math.pi / 2))
    np.testing.assert_allclose(b.to_world((1.0, 0.0)), [1.0, 3.0], atol=1e-12)
    np.testing.assert_allclose(b.to_world((0.0, 2.0)), [-1.0, 2.0], atol=1e-12)
    np.testing.assert_allclose(b.to_local((1.0, 3.0)), [1.0, 0.0], atol=1e-12)
    rng = np.random.default_rng(0)
    b.angle = 0.7
    for point in rng.normal(size=(20, 2)) * 5:
        np.testing.assert_allclose(b.to_local(b.to_world(point)), point, atol=1e-12)
    batch = p2.World(batch_size=2)
    c = batch.add(p2.Circle())
    c.position = [[0.0, 0.0], [1.0, 1.0]]
    c.angle = [0.0, math.pi]
    np.testing.assert_allclose(c.to_world((1.0, 0.0)), [[1.0, 0.0], [0.0, 1.0]], atol=1e-12)
    np.testing.assert_allclose(c.to_local((1.0, 0.0)), [[1.0, 0.0], [0.0, 1.0]], atol=1e-12)


def test_replicate_maps_bodies_to_independent_copies():
    """replicate(n).bodies[i] is an independent batched copy of the original bodies[i]."""
    world = p2.World()
    g = world.add(p2.Plane())
    c = world.add(p2.Circle(position=(0.0, 2.0), velocity=(1.0, 0.0), radius=0.3))
    b = world.add(p2.Box(position=(2.0, 0.5), width=1.0, height=1.0, angle=0.2))
    s = world.add(p2.Spring(c, b, rest_length=1.0, stiffness=2.0))
    copy = world.replicate(8)
    assert copy.batch_size == 8 and world.batch_size == 1
    assert len(copy.bodies) == 3 and len(copy.springs) == 1
    for original, twin in zip(world.bodies, copy.bodies, strict=True):
        assert type(twin) is type(original) and twin is not original
        assert twin.world is copy and twin.slot == original.slot
    cc, cb = copy.bodies[1], copy.bodies[2]
    np.testing.assert_array_equal(cc.position, np.tile(c.position, (8, 1)))
    np.testing.assert_array_equal(cb.angle, np.full(8, b.angle))
    np.testing.assert_array_equal(copy.bodies[0].point, np.tile(g.point, (8, 1)))
    assert copy.springs[0].body1 is cc and copy.springs[0].body2 is cb
    np.testing.assert_array_equal(copy.springs[0].stiffness, np.full(8, s.stiffness))
    cc.position = (5.0, 5.0)
    steps(copy, 5)
    np.testing.assert_array_equal(c.position, [0.0, 2.0])
    assert world.steps == 0


def test_impulses_report_how_hard_each_body_was_hit():
    """World.impulses: a resting body receives m g dt per step; a body stopped dead by a
    plane receives its momentum (summed over the steps of the impact)."""
    world = p2.World(gravity=(0.0, -9.81), sleeping=False)
    world.add(p2.Plane())
    ball = world.add(p2.Circle(position=(0, 2.0), radius=0.5, mass=2.0))
    dt, received, momentum = 1 / 60, 0.0, 0.0
    while received == 0.0:
        momentum = -ball.mass * ball.velocity[1]
        world.step(dt)
        received = world.impulses()[ball.slot]
    for _ in range(3):
        world.step(dt)
        received += world.impulses()[ball.slot]
    assert received == pytest.approx(momentum + 4 * ball.mass * 9.81 * dt, rel=0.05)
    world.step(dt)
    assert world.impulses()[ball.slot] == pytest.approx(ball.mass * 9.81 * dt, rel=1e-6)
    batch = world.replicate(3)
    batch.step(dt)
    assert batch.impulses().shape == (3, world.state.body.shape[1])


def test_at_rest_and_stop():
    """at_rest is True once everything sleeps; stop() brings chosen worlds to rest at once,
    and a stopped body stays put until something touches it."""
    world = p2.World(gravity=(0.0, 0.0)).replicate(2)
    ball = world.add(p2.Circle(velocity=(1.0, 0.0)))
    assert not world.at_rest().any()
    world.stop(worlds=[1])
    np.testing.assert_array_equal(world.at_rest(), [False, True])
    world.step(1 / 60)
    assert ball.position[1, 0] == 0.0 and ball.position[0, 0] > 0.0
    with pytest.raises(ValueError, match="worlds"):
        world.stop(worlds=[2])
