"""Public-contract tests: every documented name, keyword and behaviour of the user API.

These tests pin what a user of ``impulse2d`` relies on (construction, properties,
setters, forces, impulses, removal, body kinds, material mixing, sleeping and batches),
not how the engine computes it.
"""

from __future__ import annotations

import inspect
import math

import numpy as np
import pytest

import impulse2d as p2

DT = 1.0 / 60.0
G = 9.81


# -- helpers ---------------------------------------------------------------------------------------
def steps(world: p2.World, n: int, dt: float = DT) -> None:
    for _ in range(n):
        world.step(dt)


def cross(r, f) -> float:
    return float(r[0] * f[1] - r[1] * f[0])


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


def resting_circle_world(**world_kwargs) -> tuple[p2.World, p2.Circle]:
    world = p2.World(**world_kwargs)
    world.add(p2.Plane(normal=(0.0, 1.0), point=(0.0, 0.0)))
    ball = world.add(p2.Circle(position=(0.0, 0.5), radius=0.5, mass=1.0))
    return world, ball


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
    assert batch.impulses().shape == (3, world._bodies.capacity)


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
