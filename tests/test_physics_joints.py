"""Joints against known answers: a pendulum's period on a revolute joint, a motor's speed
and torque limit, a spring's period, a slider's limit, a weld holding a cantilever, a
rod and a rope, a breaking joint, the mouse joint's pull and its force limit, energy
and momentum with joints, and joined bodies kept from colliding."""

from __future__ import annotations

import math

import numpy as np
import pytest

import impulse2d as p2

G = 9.81
DT = 1 / 60


def crossings(samples: np.ndarray, dt: float) -> np.ndarray:
    """Times of the upward zero crossings of ``samples`` (linear between samples)."""
    s = np.asarray(samples)
    k = np.flatnonzero((s[:-1] < 0.0) & (s[1:] >= 0.0))
    return (k + s[k] / (s[k] - s[k + 1])) * dt


def period(world: p2.World, read, dt: float, seconds: float) -> float:
    samples = []
    for _ in range(round(seconds / dt)):
        world.step(dt)
        samples.append(read())
    times = crossings(np.array(samples), dt)
    assert len(times) >= 3
    return float(np.mean(np.diff(times)))


def test_a_pendulum_on_a_revolute_joint_swings_with_its_period():
    """A small disc on a massless pivot 1 m away, let go 5 degrees out: the period of a
    compound pendulum ``2 pi sqrt(I / (m g L))``, ``I = m (L^2 + r^2 / 2)`` (0.5 %)."""
    world = p2.World(substeps=8)
    pivot = world.add(p2.Circle(radius=0.05, position=(0.0, 0.0), fixed=True))
    length, radius, start = 1.0, 0.05, math.radians(5.0)
    bob = world.add(
        p2.Circle(radius=radius, position=(length * math.sin(start), -length * math.cos(start)))
    )
    world.add(p2.RevoluteJoint(pivot, bob, anchor=(0.0, 0.0)))
    expected = 2 * math.pi * math.sqrt((length**2 + 0.5 * radius**2) / (G * length))
    measured = period(world, lambda: float(bob.position[0]), 1 / 240, 8.0)
    assert measured == pytest.approx(expected, rel=0.005)


def test_a_motor_spins_up_at_its_torque_limit_and_holds_its_speed():
    """A free wheel on a fixed axle, motor 5 rad/s with at most 2 N m: the speed grows as
    ``tau t / I`` until it reaches 5 rad/s and stays there (1e-6); the joint reports the
    torque while it spins up."""
    world = p2.World(gravity=(0.0, 0.0))
    axle = world.add(p2.Circle(radius=0.1, position=(0.0, 0.0), fixed=True))
    wheel = world.add(p2.Circle(radius=0.5, mass=2.0))
    motor = world.add(p2.RevoluteJoint(axle, wheel, motor_speed=5.0, max_motor_torque=2.0))
    moment = 0.5 * 2.0 * 0.25
    world.step(DT, 6)  # 0.1 s
    assert wheel.angular_velocity == pytest.approx(2.0 * 0.1 / moment, rel=1e-6)
    assert motor.torque == pytest.approx(2.0, rel=1e-6)
    world.step(DT, 60)
    assert wheel.angular_velocity == pytest.approx(5.0, abs=1e-6)


def test_a_revolute_spring_oscillates_at_its_frequency():
    """A revolute joint's angular spring of 2 Hz on a free wheel (no damping): the wheel
    swings back and forth at 2 Hz (1 %)."""
    world = p2.World(gravity=(0.0, 0.0), sleeping=False)
    axle = world.add(p2.Circle(radius=0.1, fixed=True))
    wheel = world.add(p2.Box(width=1.0, height=0.2))
    world.add(p2.RevoluteJoint(axle, wheel, spring_hertz=2.0))
    wheel.angular_velocity = 1.0
    measured = period(world, lambda: float(wheel.angle), 1 / 240, 3.0)
    assert measured == pytest.approx(0.5, rel=0.01)


def test_a_revolute_joints_limits_stop_the_swing():
    """A pendulum let go horizontally with its angle limited to 0.5 rad either way stops
    at the limit (within 0.01 rad) and never passes it by more than that."""
    world = p2.World(substeps=8)
    pivot = world.add(p2.Circle(radius=0.05, fixed=True))
    arm = world.add(p2.Box(width=1.0, height=0.1, position=(0.5, 0.0)))
    joint = world.add(
        p2.RevoluteJoint(pivot, arm, anchor=(0.0, 0.0), lower_angle=-0.5, upper_angle=0.5)
    )
    lowest = 0.0
    for _ in range(180):
        world.step(DT)
        lowest = min(lowest, float(joint.angle))
    assert lowest > -0.51
    assert float(joint.angle) == pytest.approx(-0.5, abs=0.01)


def test_a_slider_on_an_incline_stops_at_its_lower_limit_without_turning():
    """A block on a prismatic joint along a 30 degree axis slides down under gravity to
    its lower limit (-1 m, within 5 mm), does not turn, and stays on the axis (1 mm)."""
    world = p2.World(substeps=8)
    ground = world.add(p2.Box(width=0.2, height=0.2, position=(0.0, 0.0), fixed=True))
    axis = (math.cos(math.radians(30.0)), math.sin(math.radians(30.0)))
    block = world.add(p2.Box(width=0.4, height=0.2, position=(1.0, 2.0), angle=0.3))
    slider = world.add(p2.PrismaticJoint(ground, block, axis=axis, lower_translation=-1.0,
                                         upper_translation=1.0))  # fmt: skip
    world.step(DT, 180)
    assert float(slider.translation) == pytest.approx(-1.0, abs=5e-3)
    assert float(block.angle) == pytest.approx(0.3, abs=1e-3)
    offset = np.asarray(block.position) - np.array([1.0, 2.0])
    assert abs(offset[0] * axis[1] - offset[1] * axis[0]) < 1e-3  # no motion across the axis


def test_a_slider_motor_drives_at_its_speed():
    world = p2.World(gravity=(0.0, 0.0))
    rail = world.add(p2.Box(width=0.2, height=0.2, fixed=True))
    cart = world.add(p2.Box(width=0.4, height=0.2, position=(0.0, 1.0), mass=3.0))
    world.add(
        p2.PrismaticJoint(rail, cart, axis=(1.0, 0.0), motor_speed=0.7, max_motor_force=100.0)
    )
    world.step(DT, 30)
    np.testing.assert_allclose(cart.velocity, [0.7, 0.0], atol=1e-6)


def test_a_rigid_weld_holds_a_cantilever_and_a_soft_one_sags_more():
    """A 2 m plank welded at its end to a wall: rigid, it holds within 1 mrad and 2 mm;
    a soft weld (3 Hz, critically damped) sags further but comes to rest."""
    tips = {}
    for hertz in (0.0, 3.0):
        world = p2.World(substeps=8)
        wall = world.add(p2.Box(width=0.2, height=2.0, position=(0.0, 0.0), fixed=True))
        plank = world.add(p2.Box(width=2.0, height=0.1, position=(1.1, 0.5), mass=5.0))
        world.add(p2.WeldJoint(wall, plank, anchor=(0.1, 0.5), hertz=hertz, damping_ratio=1.0))
        world.step(DT, 240)
        tips[hertz] = float(plank.angle)
        assert abs(float(plank.angular_velocity)) < 1e-3
        if hertz == 0.0:
            assert abs(float(plank.angle)) < 1e-3
            np.testing.assert_allclose(plank.position, [1.1, 0.5], atol=2e-3)
    assert tips[3.0] < tips[0.0] - 0.01


def test_a_rod_keeps_its_length_and_a_rope_goes_slack():
    """Thrown sideways, a ball on a 1.5 m rod keeps 1.5 m (2 mm) as it swings; a ball on
    a 1.5 m rope thrown up comes closer than 1.5 m (the rope slack) and never farther
    (2 mm)."""
    world = p2.World(substeps=8)
    hook = world.add(p2.Circle(radius=0.05, fixed=True))
    rod_ball = world.add(p2.Circle(radius=0.1, position=(1.5, 0.0), velocity=(0.0, 3.0)))
    rod = world.add(p2.DistanceJoint(hook, rod_ball))
    rope_hook = world.add(p2.Circle(radius=0.05, position=(5.0, 0.0), fixed=True))
    rope_ball = world.add(p2.Circle(radius=0.1, position=(5.0, -1.5), velocity=(0.0, 4.0)))
    rope = world.add(p2.DistanceJoint(rope_hook, rope_ball, min_length=0.0))
    rod_lengths, rope_lengths = [], []
    for _ in range(120):
        world.step(DT)
        rod_lengths.append(float(rod.current_length))
        rope_lengths.append(float(rope.current_length))
    assert max(abs(length - 1.5) for length in rod_lengths) < 2e-3
    assert min(rope_lengths) < 1.0 and max(rope_lengths) < 1.502


def test_a_weak_joint_breaks_and_a_strong_one_holds():
    """A 1 kg plank welded to a wall needs about 9.81 N: a weld that breaks past 5 N
    switches itself off at once and the plank falls; one of 50 N holds."""
    for break_force, holds in ((5.0, False), (50.0, True)):
        world = p2.World()
        wall = world.add(p2.Box(width=0.2, height=2.0, fixed=True))
        plank = world.add(p2.Box(width=1.0, height=0.1, position=(0.6, 0.5)))
        weld = world.add(p2.WeldJoint(wall, plank, anchor=(0.1, 0.5), break_force=break_force))
        world.step(DT, 30)
        assert bool(weld.enabled) is holds
        assert (float(plank.position[1]) > 0.49) is holds
    assert np.hypot(*weld.force) == pytest.approx(G, rel=0.01)


def test_the_mouse_joint_drags_a_body_to_its_target_within_its_force():
    """Without gravity a box dragged to a target 3 m away gets there (1 cm, 3 s); with a
    weak force limit it accelerates at most ``F / m``."""
    world = p2.World(gravity=(0.0, 0.0))
    box = world.add(p2.Box(width=0.5, height=0.5, mass=2.0))
    drag = world.add(p2.MouseJoint(box, target=(0.0, 0.0), max_force=4.0))
    drag.target = (3.0, 0.0)
    world.step(DT, 30)
    assert float(np.hypot(*box.velocity)) <= 4.0 / 2.0 * 0.5 + 1e-9
    assert float(np.hypot(*drag.force)) <= 4.0 + 1e-9
    drag.max_force = 1000.0
    world.step(DT, 180)
    np.testing.assert_allclose(box.position, [3.0, 0.0], atol=0.01)


def test_a_double_pendulum_keeps_its_energy_and_a_free_pair_its_momentum():
    """A chain of two rigid links swinging from rest: the total energy stays within 2 %
    of the drop over 5 s. Two bodies pinned together and thrown spinning without gravity:
    linear momentum is kept to rounding (the joint's impulses are equal and opposite);
    angular momentum about the origin to 0.1 % (they act at anchors the soft joint keeps
    together only to its position error, so the couple of that gap changes it)."""
    world = p2.World(substeps=8, sleeping=False)
    pivot = world.add(p2.Circle(radius=0.05, fixed=True))
    first = world.add(p2.Box(width=1.0, height=0.1, position=(0.5, 0.0)))
    second = world.add(p2.Box(width=1.0, height=0.1, position=(1.5, 0.0)))
    world.add(p2.RevoluteJoint(pivot, first, anchor=(0.0, 0.0)))
    world.add(p2.RevoluteJoint(first, second, anchor=(1.0, 0.0)))
    start = world.energy().total
    drift = 0.0
    for _ in range(300):
        world.step(DT)
        drift = max(drift, abs(world.energy().total - start))
    assert drift < 0.02 * (2.0 * G * 1.0)

    free = p2.World(gravity=(0.0, 0.0), sleeping=False)
    a = free.add(
        p2.Box(
            width=1.0, height=0.2, position=(0.0, 0.0), velocity=(1.0, 0.5), angular_velocity=2.0
        )
    )
    b = free.add(p2.Circle(radius=0.3, position=(0.8, 0.0), mass=3.0, velocity=(-1.0, 0.0)))
    free.add(p2.RevoluteJoint(a, b, anchor=(0.6, 0.0)))

    def momenta():
        linear = sum(x.mass * np.asarray(x.velocity) for x in (a, b))
        angular = sum(
            x.moment * x.angular_velocity
            + x.mass * (x.position[0] * x.velocity[1] - x.position[1] * x.velocity[0])
            for x in (a, b)
        )
        return linear, angular

    linear0, angular0 = momenta()
    free.step(DT, 120)
    linear, angular = momenta()
    np.testing.assert_allclose(linear, linear0, atol=1e-12)
    assert angular == pytest.approx(angular0, rel=1e-3)


@pytest.mark.parametrize("collide", [False, True])
def test_joined_bodies_collide_only_when_asked(collide):
    """Two overlapping boxes pinned together: by default no contact between them (a
    ragdoll's overlapping limbs); with ``collide_connected=True`` they touch."""
    world = p2.World(gravity=(0.0, 0.0))
    a = world.add(p2.Box(width=1.0, height=0.3, position=(0.0, 0.0)))
    b = world.add(p2.Box(width=1.0, height=0.3, position=(0.8, 0.0)))
    world.add(p2.RevoluteJoint(a, b, anchor=(0.45, 0.0), collide_connected=collide))
    other = world.add(p2.Box(width=0.3, height=0.3, position=(0.0, 0.3)))
    world.step(DT)
    contacts = world.contacts()
    pairs = {
        frozenset(p) for p in zip(contacts.slot_a.tolist(), contacts.slot_b.tolist(), strict=True)
    }
    assert (frozenset((a.slot, b.slot)) in pairs) is collide
    assert frozenset((a.slot, other.slot)) in pairs  # others still collide with them
