"""Public-contract tests, objects: the documented names, keywords, properties and calls.

These tests pin what a user of ``impulse2d`` relies on when building and handling bodies,
planes and springs (construction, properties, setters, forces, impulses and removal), not
how the engine computes it. Body kinds, material mixing, sleeping and batches are in
``test_contract_world.py``.
"""

from __future__ import annotations

import inspect
import math

import numpy as np
import pytest

import impulse2d as p2
from conftest import DT, resting_circle_world, steps


# -- helpers ---------------------------------------------------------------------------------------
def cross(r, f) -> float:
    return float(r[0] * f[1] - r[1] * f[0])


def asleep_circle() -> tuple[p2.World, p2.Circle]:
    world, ball = resting_circle_world()
    steps(world, 60)
    assert not ball.awake, "precondition: a ball at rest on a plane falls asleep within 1 s"
    return world, ball


# -- names, keywords and defaults ------------------------------------------------------------------
def test_world_signature_and_defaults():
    """World takes gravity then every documented setting keyword-only, with its default."""
    params = inspect.signature(p2.World).parameters
    expected = {
        "batch_size": 1,
        "substeps": 4,
        "restitution_mixing": "max",
        "friction_mixing": "sqrt",
        "restitution_threshold": 1.0,
        "contact_hertz": 30.0,
        "contact_damping_ratio": 10.0,
        "contact_push_speed": 3.0,
        "speculative_distance": 0.02,
        "sleeping": True,
        "time_to_sleep": 0.5,
        "sleep_speed": 0.05,
    }
    assert tuple(params["gravity"].default) == (0.0, -9.81)
    assert params["gravity"].kind is inspect.Parameter.POSITIONAL_OR_KEYWORD
    for name, default in expected.items():
        assert params[name].kind is inspect.Parameter.KEYWORD_ONLY, name
        assert params[name].default == default, name
    world = p2.World((0.0, -1.0), **expected)
    np.testing.assert_array_equal(world.gravity, [0.0, -1.0])
    assert world.batch_size == 1
    assert np.array_equal(p2.World().gravity, [0.0, -9.81])


def test_public_names_exported():
    """The package exports World, Circle, Box, Plane and Spring."""
    for name in ("World", "Circle", "Box", "Plane", "Spring"):
        assert hasattr(p2, name), name


@pytest.mark.parametrize("cls", [p2.Circle, p2.Box])
def test_body_accepts_every_keyword_and_reads_it_back(cls):
    """Circle and Box accept every documented keyword and read it back before and after add."""
    size = {"radius": 0.5} if cls is p2.Circle else {"width": 1.0, "height": 0.5}
    given = dict(
        position=(0.5, 5.0),
        velocity=(1.0, -2.0),
        angle=0.25,
        angular_velocity=-1.5,
        mass=2.0,
        restitution=0.5,
        friction=0.3,
        linear_drag=0.1,
        angular_drag=0.2,
        **size,
    )
    body = cls(**given, fixed=False, kinematic=False)

    def check() -> None:
        for name, value in given.items():
            got = getattr(body, name)
            np.testing.assert_array_equal(got, value, err_msg=name)
        assert body.fixed is False and body.kinematic is False

    check()
    world = p2.World()
    assert world.add(body) is body
    check()
    assert isinstance(body.position, np.ndarray) and body.position.shape == (2,)
    assert isinstance(body.velocity, np.ndarray) and body.velocity.shape == (2,)
    for name in ("angle", "angular_velocity", "mass", "moment", *size):
        assert isinstance(getattr(body, name), float), name
    assert body.awake is True
    assert body.enabled is True


def test_add_returns_the_object_and_lists_are_in_slot_order():
    """add returns the object; bodies/springs list objects in slot order; world/slot are set."""
    world = p2.World()
    c = p2.Circle(position=(0.0, 5.0), radius=0.5)
    b = p2.Box(position=(2.0, 5.0), width=1.0, height=0.5, mass=2.0, angle=0.3)
    g = p2.Plane(normal=(0.0, 1.0), point=(0.0, 0.0), restitution=0.0, friction=0.5)
    assert c.world is None and c.slot == -1
    assert world.add(c) is c
    assert world.add(b) is b
    assert world.add(g) is g
    s = p2.Spring(
        c, b, rest_length=2.0, stiffness=50.0, damping=0.1, anchor1=(0, 0), anchor2=(0.5, 0)
    )
    assert world.add(s) is s
    assert world.bodies == [c, b, g]
    assert world.springs == [s]
    assert [obj.world for obj in (c, b, g, s)] == [world] * 4
    assert [obj.slot for obj in world.bodies] == sorted(obj.slot for obj in world.bodies)
    assert len({c.slot, b.slot, g.slot}) == 3
    world.step(DT)
    world.remove(s)
    assert world.springs == [] and s.world is None
    world.remove(c)
    assert world.bodies == [b, g] and c.world is None and c.slot == -1


def test_vector_properties_return_copies():
    """Mutating an array a property returned leaves body, plane, spring and world unchanged."""
    world = p2.World()
    c = world.add(p2.Circle(position=(1.0, 2.0), velocity=(3.0, 4.0)))
    d = world.add(p2.Circle(position=(4.0, 2.0)))
    g = world.add(p2.Plane(normal=(0.0, 1.0), point=(0.0, -1.0)))
    s = world.add(p2.Spring(c, d, anchor1=(0.1, 0.0), anchor2=(0.0, 0.2)))
    for obj, name in (
        (c, "position"),
        (c, "velocity"),
        (g, "point"),
        (g, "normal"),
        (s, "anchor1"),
        (s, "anchor2"),
        (world, "gravity"),
    ):
        before = getattr(obj, name).copy()
        getattr(obj, name)[...] = 99.0
        np.testing.assert_array_equal(getattr(obj, name), before, err_msg=name)
    detached = p2.Circle(position=(1.0, 1.0))
    detached.position[0] = 50.0
    np.testing.assert_array_equal(detached.position, [1.0, 1.0])


def test_batch_properties_return_copies():
    """In a batch, mutating returned per-world arrays leaves the body unchanged."""
    world = p2.World(batch_size=3)
    c = world.add(p2.Circle(position=(1.0, 2.0), angle=0.5))
    for name in (
        "position",
        "velocity",
        "angle",
        "angular_velocity",
        "mass",
        "radius",
        "awake",
        "enabled",
    ):
        before = getattr(c, name).copy()
        array = getattr(c, name)
        array[...] = not array.flat[0] if array.dtype == bool else 7.0
        np.testing.assert_array_equal(getattr(c, name), before, err_msg=name)


def test_moment_is_derived_from_mass_and_size():
    """moment is m r^2/2 (circle), m(w^2+h^2)/12 (box) and follows mass and size setters."""
    world = p2.World()
    c = world.add(p2.Circle(radius=0.5, mass=2.0))
    b = world.add(p2.Box(position=(3.0, 0.0), width=1.0, height=0.5, mass=2.0))
    assert c.moment == pytest.approx(0.5 * 2.0 * 0.25, rel=1e-12)
    assert b.moment == pytest.approx(2.0 * (1.0 + 0.25) / 12.0, rel=1e-12)
    c.mass = 3.0
    c.radius = 0.8
    b.mass = 4.0
    b.width = 2.0
    b.height = 0.3
    assert c.radius == 0.8 and c.mass == 3.0
    assert c.moment == pytest.approx(0.5 * 3.0 * 0.64, rel=1e-12)
    assert (b.width, b.height, b.mass) == (2.0, 0.3, 4.0)
    assert b.moment == pytest.approx(4.0 * (4.0 + 0.09) / 12.0, rel=1e-12)
    detached = p2.Box(width=3.0, height=4.0, mass=6.0)
    assert detached.moment == pytest.approx(6.0 * 25.0 / 12.0, rel=1e-12)


def test_moment_is_used_by_the_dynamics():
    """After resizing, an impulse's angular effect uses the new moment (r x J)/I."""
    world = p2.World(gravity=(0.0, 0.0))
    b = world.add(p2.Box(width=1.0, height=1.0, mass=1.0))
    b.width, b.height, b.mass = 2.0, 0.5, 3.0
    b.apply_impulse((0.0, 1.0), point=(1.0, 0.0))
    expected = 1.0 / (3.0 * (4.0 + 0.25) / 12.0)
    assert b.angular_velocity == pytest.approx(expected, rel=1e-12)


# -- setters ---------------------------------------------------------------------------------------
def test_set_state_is_what_the_next_step_starts_from():
    """A set position, velocity, angle and angular velocity are what the next step starts from."""
    world = p2.World(gravity=(0.0, 0.0))
    b = world.add(p2.Box(position=(0.0, 0.0), width=1.0, height=1.0))
    world.step(DT)
    b.position = (10.0, -3.0)
    b.velocity = (2.0, 1.0)
    b.angle = 0.5
    b.angular_velocity = -3.0
    world.step(0.1)
    np.testing.assert_allclose(b.position, [10.2, -2.9], rtol=0, atol=1e-12)
    np.testing.assert_array_equal(b.velocity, [2.0, 1.0])
    assert b.angle == pytest.approx(0.5 - 0.3, abs=1e-12)
    assert b.angular_velocity == -3.0


def test_set_velocity_on_a_sleeping_body_takes_effect():
    """Setting the velocity of a sleeping body wakes it and the next step moves it."""
    world, ball = asleep_circle()
    ball.velocity = (1.0, 0.0)
    assert ball.awake
    x0 = ball.position[0]
    world.step(DT)
    assert ball.position[0] > x0 + 0.5 * DT


def test_set_position_of_a_sleeping_body_takes_effect():
    """Teleporting a sleeping body wakes it, and gravity acts from the new position."""
    world, ball = asleep_circle()
    ball.position = (2.0, 3.0)
    assert ball.awake
    world.step(DT)
    assert ball.position[0] == pytest.approx(2.0, abs=1e-12)
    assert ball.position[1] < 3.0


def test_material_and_drag_setters():
    """Material and drag setters work on bodies and planes, and drag takes effect."""
    world = p2.World(gravity=(0.0, 0.0))
    c = world.add(p2.Circle(velocity=(1.0, 0.0), angular_velocity=1.0))
    g = world.add(p2.Plane(point=(0.0, -10.0)))
    for name, value in (
        ("restitution", 0.7),
        ("friction", 0.2),
        ("linear_drag", 0.5),
        ("angular_drag", 1.0),
    ):
        setattr(c, name, value)
        assert getattr(c, name) == value
    g.restitution, g.friction = 0.4, 0.9
    assert (g.restitution, g.friction) == (0.4, 0.9)
    g.point = (0.0, -20.0)
    np.testing.assert_array_equal(g.point, [0.0, -20.0])
    steps(world, 60)
    assert c.velocity[0] == pytest.approx(math.exp(-0.5), rel=1e-3)
    assert c.angular_velocity == pytest.approx(math.exp(-1.0), rel=1e-3)


def test_gravity_setter_and_world_readouts():
    """gravity is settable with shape (2,) and acts; time and steps count what was stepped."""
    world = p2.World(gravity=(0.0, 0.0), sleeping=False)
    c = world.add(p2.Circle())
    assert world.time == 0.0 and world.steps == 0
    world.gravity = (1.0, -2.0)
    assert world.gravity.shape == (2,)
    np.testing.assert_array_equal(world.gravity, [1.0, -2.0])
    steps(world, 10, 0.1)
    assert world.steps == 10
    assert world.time == pytest.approx(1.0, rel=1e-12)
    np.testing.assert_allclose(c.velocity, [1.0, -2.0], rtol=1e-12)


# -- forces and impulses ---------------------------------------------------------------------------
def test_apply_force_acts_for_exactly_one_step():
    """apply_force changes velocity by F dt / m over the next step and not at all after."""
    world = p2.World(gravity=(0.0, 0.0))
    c = world.add(p2.Circle(mass=2.0))
    c.apply_force((4.0, -2.0))
    np.testing.assert_array_equal(c.velocity, [0.0, 0.0])  # a force is not an impulse
    world.step(0.1)
    np.testing.assert_allclose(c.velocity, [0.2, -0.1], rtol=1e-12)
    assert c.angular_velocity == 0.0
    after_one = c.velocity
    world.step(0.1)
    np.testing.assert_array_equal(c.velocity, after_one)


def test_apply_force_off_centre_gives_torque():
    """A force at a world point off the centre changes angular velocity by (r x F) dt / I."""
    world = p2.World(gravity=(0.0, 0.0))
    b = world.add(p2.Box(position=(1.0, 2.0), width=2.0, height=1.0, mass=3.0, angle=0.4))
    force, r = np.array([1.0, 3.0]), np.array([0.5, -0.25])
    b.apply_force(force, point=b.position + r)
    world.step(0.1)
    np.testing.assert_allclose(b.velocity, force * 0.1 / 3.0, rtol=1e-12)
    assert b.angular_velocity == pytest.approx(cross(r, force) * 0.1 / b.moment, rel=1e-12)
    spin = b.angular_velocity
    world.step(0.1)
    assert b.angular_velocity == spin


def test_apply_force_wakes_a_sleeping_body_and_acts():
    """A force on a sleeping body wakes it and moves it over the next step."""
    world, ball = asleep_circle()
    ball.apply_force((60.0, 0.0))
    assert ball.awake
    world.step(DT)
    assert ball.velocity[0] > 0.5


def test_apply_impulse_changes_velocity_at_once():
    """apply_impulse changes velocity by J/m and angular velocity by (r x J)/I immediately."""
    world = p2.World(gravity=(0.0, 0.0))
    b = world.add(
        p2.Box(
            position=(1.0, 2.0),
            width=2.0,
            height=1.0,
            mass=4.0,
            velocity=(1.0, 1.0),
            angular_velocity=0.5,
        )
    )
    impulse, r = np.array([2.0, -1.0]), np.array([-0.3, 0.4])
    b.apply_impulse(impulse, point=b.position + r)
    np.testing.assert_allclose(b.velocity, [1.5, 0.75], rtol=1e-12)
    assert b.angular_velocity == pytest.approx(0.5 + cross(r, impulse) / b.moment, rel=1e-12)
    c = world.add(p2.Circle(position=(10.0, 0.0), mass=2.0))
    c.apply_impulse((1.0, 2.0))
    np.testing.assert_allclose(c.velocity, [0.5, 1.0], rtol=1e-12)
    assert c.angular_velocity == 0.0


def test_apply_impulse_wakes_a_sleeping_body():
    """apply_impulse on a sleeping body wakes it with the new velocity."""
    world, ball = asleep_circle()
    ball.apply_impulse((2.0, 0.0))
    assert ball.awake
    np.testing.assert_allclose(ball.velocity, [2.0, 0.0], atol=1e-12)
    world.step(DT)
    assert ball.position[0] > 0.02


def test_wake_method_wakes_a_sleeping_body():
    """body.wake() makes a sleeping body awake."""
    _, ball = asleep_circle()
    ball.wake()
    assert ball.awake


# -- removal ---------------------------------------------------------------------------------------
def test_remove_then_add_keeps_user_values():
    """Removed circle, box, plane and spring keep every user-set value, also after re-adding."""
    world = p2.World()
    g = world.add(p2.Plane(normal=(1.0, 2.0), point=(0.0, 0.1), restitution=0.3, friction=0.2))
    c = world.add(p2.Circle(position=(1.0, 2.0), radius=0.7))
    b = world.add(p2.Box(position=(3.0, 2.0), width=0.8, height=0.6, mass=2.0, angle=0.1))
    s = world.add(
        p2.Spring(
            c,
            b,
            rest_length=1.5,
            stiffness=3.0,
            damping=0.2,
            anchor1=(0.1, 0.2),
            anchor2=(-0.3, 0.0),
        )
    )
    world.step(DT)
    c.position, c.velocity, c.angle, c.angular_velocity = (5.0, 6.0), (1.0, -1.0), 1.0, -2.0
    c.mass, c.radius = 4.5, 0.9
    c.restitution, c.friction, c.linear_drag, c.angular_drag = 0.6, 0.9, 0.05, 0.07
    b.width, b.height, b.mass = 1.3, 0.4, 7.0
    s.stiffness, s.rest_length = 4.0, 2.5
    names = (
        "position",
        "velocity",
        "angle",
        "angular_velocity",
        "mass",
        "moment",
        "restitution",
        "friction",
        "linear_drag",
        "angular_drag",
    )
    saved = {
        c: {n: getattr(c, n) for n in (*names, "radius")},
        b: {n: getattr(b, n) for n in (*names, "width", "height")},
        g: {n: getattr(g, n) for n in ("point", "normal", "restitution", "friction")},
        s: {
            n: getattr(s, n) for n in ("rest_length", "stiffness", "damping", "anchor1", "anchor2")
        },
    }

    def check() -> None:
        for obj, values in saved.items():
            for name, value in values.items():
                np.testing.assert_array_equal(getattr(obj, name), value, err_msg=f"{obj!r}.{name}")

    world.remove(s)
    for obj in (c, b, g):
        world.remove(obj)
    assert world.bodies == [] and world.springs == []
    check()
    steps(world, 3)
    check()
    for obj in (g, c, b, s):
        world.add(obj)
    check()


def test_removed_body_is_not_stepped_and_does_not_collide():
    """A removed body keeps its state while the world steps, and nothing collides with it."""
    world = p2.World()
    world.add(p2.Plane())
    shelf = world.add(p2.Box(position=(0.0, 2.0), width=4.0, height=0.2, fixed=True))
    ball = world.add(p2.Circle(position=(0.0, 3.0), radius=0.5))
    faller = world.add(p2.Circle(position=(5.0, 4.0), velocity=(1.0, 0.0), radius=0.5))
    steps(world, 60)
    assert ball.position[1] == pytest.approx(2.6, abs=0.01)  # resting on the shelf
    world.remove(faller)
    state = (faller.position, faller.velocity, faller.angle)
    world.remove(shelf)
    steps(world, 90)
    np.testing.assert_array_equal(faller.position, state[0])
    np.testing.assert_array_equal(faller.velocity, state[1])
    assert faller.angle == state[2]
    assert ball.position[1] == pytest.approx(0.5, abs=0.01)  # fell through where the shelf was


def test_removed_spring_exerts_no_force():
    """After a stretched spring is removed, its bodies feel no force from it."""
    world = p2.World(gravity=(0.0, 0.0))
    a = world.add(p2.Circle(position=(0.0, 0.0)))
    b = world.add(p2.Circle(position=(3.0, 0.0)))
    s = world.add(p2.Spring(a, b, rest_length=1.0, stiffness=10.0))
    world.step(DT)
    assert a.velocity[0] > 0.0 and b.velocity[0] < 0.0
    world.remove(s)
    va, vb = a.velocity, b.velocity
    steps(world, 10)
    np.testing.assert_array_equal(a.velocity, va)
    np.testing.assert_array_equal(b.velocity, vb)


def test_removing_a_body_attached_to_a_spring_raises():
    """Removing a body held by a spring raises ValueError and changes nothing."""
    world = p2.World(gravity=(0.0, 0.0))
    a = world.add(p2.Circle(position=(0.0, 0.0)))
    b = world.add(p2.Circle(position=(3.0, 0.0)))
    s = world.add(p2.Spring(a, b, rest_length=1.0, stiffness=10.0))
    for body in (a, b):
        with pytest.raises(ValueError):
            world.remove(body)
    assert world.bodies == [a, b] and world.springs == [s]
    assert a.world is world and s.world is world
    world.step(DT)
    assert a.velocity[0] > 0.0  # the spring still pulls
    world.remove(s)
    world.remove(a)
    assert world.bodies == [b]
