"""Physics laws of free motion: gravity, drag, forces and impulses (no contacts)."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

import impulse2d as p2
from conftest import DT, G, run, trace


def _free_flight_error(dt: float, v0: tuple[float, float], seconds: float = 1.0) -> float:
    """Position error (m) after ``seconds`` of flight against x0 + v0 t + g t^2 / 2."""
    world = p2.World(gravity=(0.0, -G), sleeping=False)
    ball = world.add(p2.Circle(position=(0.0, 10.0), radius=0.5, velocity=v0))
    run(world, seconds, dt)
    t = world.time
    exact = np.array([v0[0] * t, 10.0 + v0[1] * t - 0.5 * G * t * t])
    return float(np.linalg.norm(ball.position - exact))


@pytest.mark.parametrize("v0", [(3.0, 4.0), (-2.0, 0.0), (0.0, -5.0)])
def test_free_flight_parabola_first_order(v0):
    """Free flight: x = x0 + v0 t + g t^2/2, v = v0 + g t; the error is O(dt)."""
    errors = [_free_flight_error(dt, v0) for dt in (DT, DT / 2, DT / 4)]
    assert errors[0] < 0.03  # small at dt = 1/60 (2 cm after 1 s)
    for coarse, fine in itertools.pairwise(errors):
        assert 1.8 < coarse / fine < 2.2  # first order: halving dt halves the error

    world = p2.World(sleeping=False)
    ball = world.add(p2.Circle(position=(0.0, 10.0), velocity=v0))
    run(world, 1.0)
    expected = np.array([v0[0], v0[1] - G * world.time])
    np.testing.assert_allclose(ball.velocity, expected, atol=1e-9)


@pytest.mark.parametrize("shape", ["circle", "box"])
def test_zero_gravity_constant_velocity(shape):
    """Newton's first law: with g = 0, x = x0 + v t and theta = theta0 + w t exactly."""
    world = p2.World(gravity=(0.0, 0.0), sleeping=False)
    kwargs = dict(position=(1.0, 2.0), velocity=(3.0, -1.5), angle=0.2, angular_velocity=2.0)
    body = world.add(p2.Circle(**kwargs) if shape == "circle" else p2.Box(**kwargs))
    run(world, 2.0)
    t = world.time
    np.testing.assert_allclose(body.velocity, [3.0, -1.5], atol=1e-12)
    np.testing.assert_allclose(body.position, [1.0 + 3.0 * t, 2.0 - 1.5 * t], atol=1e-9)
    assert body.angular_velocity == pytest.approx(2.0, abs=1e-12)
    assert body.angle == pytest.approx(0.2 + 2.0 * t, abs=1e-9)


def test_gravity_is_a_world_setting():
    """g is per world and settable: after ``w.gravity = g'``, dv/dt = g'."""
    world = p2.World(gravity=(0.0, -G), sleeping=False)
    np.testing.assert_allclose(world.gravity, [0.0, -G])
    ball = world.add(p2.Circle(position=(0.0, 0.0)))
    run(world, 0.5)
    np.testing.assert_allclose(ball.velocity, [0.0, -G * 0.5], atol=1e-9)
    world.gravity = (2.0, -1.62)
    np.testing.assert_allclose(world.gravity, [2.0, -1.62])
    v_before = ball.velocity
    run(world, 1.0)
    np.testing.assert_allclose(ball.velocity - v_before, [2.0, -1.62], atol=1e-9)


def test_gravity_change_wakes_resting_body():
    """Reversing g makes a body resting (asleep) on the ground fall upwards: a = g'."""
    world = p2.World(gravity=(0.0, -G))
    world.add(p2.Plane(normal=(0.0, 1.0), point=(0.0, 0.0)))
    box = world.add(p2.Box(position=(0.0, 0.5)))
    run(world, 2.0)
    assert not box.awake  # it went to sleep on the ground
    world.gravity = (0.0, G)
    run(world, 1.0)
    assert box.position[1] > 0.5 + 0.4 * G * 1.0**2  # ~ 0.5 + g t^2 / 2 = 5.4 m
    assert box.velocity[1] == pytest.approx(G * 1.0, rel=0.02)


@pytest.mark.parametrize("drag", [0.3, 1.0, 3.0])
def test_linear_drag_exponential_decay(drag):
    """Linear drag d: v(t) = v0 exp(-d t) (within 2%), with g = 0."""
    world = p2.World(gravity=(0.0, 0.0), sleeping=False)
    body = world.add(p2.Box(velocity=(4.0, -2.0), linear_drag=drag))
    t, v = trace(world, 1.5, lambda: body.velocity)
    expected = np.array([4.0, -2.0])[None, :] * np.exp(-drag * t)[:, None]
    np.testing.assert_allclose(v, expected, rtol=0.02)
    # The position is the integral: x = v0 (1 - exp(-d t)) / d.
    assert body.position[0] == pytest.approx(4.0 * (1 - np.exp(-drag * t[-1])) / drag, rel=0.02)


@pytest.mark.parametrize("drag", [0.5, 2.0])
def test_angular_drag_exponential_decay(drag):
    """Angular drag d: w(t) = w0 exp(-d t) (within 2%); linear motion is untouched."""
    world = p2.World(gravity=(0.0, 0.0), sleeping=False)
    body = world.add(p2.Box(velocity=(1.0, 0.0), angular_velocity=5.0, angular_drag=drag))
    t, w = trace(world, 1.5, lambda: body.angular_velocity)
    np.testing.assert_allclose(w, 5.0 * np.exp(-drag * t), rtol=0.02)
    np.testing.assert_allclose(body.velocity, [1.0, 0.0], atol=1e-12)


def test_drag_terminal_velocity():
    """Falling with linear drag d: v -> g / d (within 2%)."""
    world = p2.World(sleeping=False)
    body = world.add(p2.Circle(position=(0.0, 100.0), linear_drag=2.0))
    run(world, 5.0)
    assert body.velocity[1] == pytest.approx(-G / 2.0, rel=0.02)


def test_drag_energy_never_increases():
    """With drag in flight the total energy only goes down: dE/dt = -d m v^2 <= 0."""
    world = p2.World(sleeping=False)
    world.add(
        p2.Circle(
            position=(0.0, 5.0),
            velocity=(3.0, 8.0),
            angular_velocity=4.0,
            linear_drag=0.5,
            angular_drag=0.5,
        )
    )
    energy = [world.energy().total]
    for _ in range(180):
        world.step(DT)
        energy.append(world.energy().total)
    assert np.max(np.diff(energy)) <= 1e-9
    assert energy[-1] < energy[0] - 1.0


@pytest.mark.parametrize("shape", ["circle", "box"])
def test_force_newton_second_law(shape):
    """F = m a and torque = I alpha: a force held for t gives v = F t / m, w = (r x F) t / I."""
    world = p2.World(gravity=(0.0, 0.0), sleeping=False)
    if shape == "circle":
        body = world.add(p2.Circle(radius=0.5, mass=2.0))
        moment = 2.0 * 0.5**2 / 2.0
    else:
        body = world.add(p2.Box(width=1.0, height=0.5, mass=2.0))
        moment = 2.0 * (1.0**2 + 0.5**2) / 12.0
    assert body.moment == pytest.approx(moment)
    force = np.array([3.0, 1.0])
    for _ in range(60):  # the point of application moves with the body: use its centre
        body.apply_force(force)
        world.step(DT)
    np.testing.assert_allclose(body.velocity, force * world.time / 2.0, rtol=1e-9)
    assert body.angular_velocity == pytest.approx(0.0, abs=1e-12)

    # An off-centre push on a body at rest for one step: dw = (r x F) dt / I.
    world = p2.World(gravity=(0.0, 0.0), sleeping=False)
    body = world.add(p2.Box(width=1.0, height=0.5, mass=2.0))
    body.apply_force((0.0, 4.0), point=(0.5, 0.0))
    world.step(DT)
    np.testing.assert_allclose(body.velocity, [0.0, 4.0 * DT / 2.0], rtol=1e-9)
    assert body.angular_velocity == pytest.approx(0.5 * 4.0 * DT / body.moment, rel=1e-9)


@pytest.mark.parametrize("shape", ["circle", "box"])
def test_impulse_changes_momentum(shape):
    """An impulse J at r from the centre: dv = J / m, dw = (r x J) / I."""
    world = p2.World(gravity=(0.0, 0.0), sleeping=False)
    if shape == "circle":
        body = world.add(p2.Circle(position=(1.0, 1.0), radius=0.4, mass=3.0))
        moment = 3.0 * 0.4**2 / 2.0
    else:
        body = world.add(p2.Box(position=(1.0, 1.0), width=0.6, height=1.2, mass=3.0))
        moment = 3.0 * (0.6**2 + 1.2**2) / 12.0
    impulse = np.array([2.0, -1.0])
    r = np.array([0.3, 0.2])
    body.apply_impulse(impulse, point=(1.0 + r[0], 1.0 + r[1]))
    np.testing.assert_allclose(body.velocity, impulse / 3.0, rtol=1e-12)
    torque = r[0] * impulse[1] - r[1] * impulse[0]
    assert body.angular_velocity == pytest.approx(torque / moment, rel=1e-12)


@pytest.mark.parametrize(("speed", "deceleration"), [(2.0, 0.1), (5.0, 0.5)])
def test_rolling_resistance_stops_after_v2_over_2a(speed, deceleration):
    """Rolling resistance a (m/s^2) stops a body after v0/a seconds and v0^2/(2a) metres."""
    world = p2.World(gravity=(0.0, 0.0), sleeping=False)
    ball = world.add(p2.Circle(radius=0.03, velocity=(speed, 0.0), rolling_resistance=deceleration))
    dt, steps = 1 / 120, 0
    while ball.velocity[0] > 0.0:
        world.step(dt)
        steps += 1
    assert steps * dt == pytest.approx(speed / deceleration, abs=2 * dt)
    assert ball.position[0] == pytest.approx(speed**2 / (2 * deceleration), rel=0.005)
    assert ball.velocity[0] == 0.0  # it stops, it does not turn around
