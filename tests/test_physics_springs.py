"""Physics laws of springs: Hooke oscillation period, energy conservation, damping rate,
two-body (reduced-mass) motion, and energy bookkeeping of spring systems."""

from __future__ import annotations

import numpy as np
import pytest

import impulse2d as p2
from conftest import DT, G, contact_count, trace, upward_crossings

ZERO_G = (0.0, 0.0)


def _mass_on_spring(m: float, k: float, c: float = 0.0, amplitude: float = 0.5, gravity=ZERO_G):
    """A ball on a spring (rest length 2 m) to a small fixed body at the origin, along x,
    released at rest from L0 + amplitude."""
    world = p2.World(gravity=gravity, sleeping=False)
    anchor = world.add(p2.Circle(position=(0.0, 0.0), radius=0.05, fixed=True))
    ball = world.add(p2.Circle(position=(2.0 + amplitude, 0.0), radius=0.2, mass=m))
    world.add(p2.Spring(anchor, ball, rest_length=2.0, stiffness=k, damping=c))
    return world, ball


def _period(t: np.ndarray, x: np.ndarray) -> float:
    crossings = upward_crossings(t, x - x.mean())
    assert crossings.size >= 3
    return float(np.diff(crossings).mean())


@pytest.mark.parametrize(("m", "k"), [(1.0, 50.0), (2.0, 20.0), (0.5, 200.0), (3.0, 10.0)])
def test_spring_period(m, k):
    """Hooke's law, mass on a spring: T = 2 pi sqrt(m / k) (+-3%), amplitude kept."""
    world, ball = _mass_on_spring(m, k)
    t, x = trace(world, 4.0 * 2 * np.pi * np.sqrt(m / k), lambda: ball.position[0] - 2.0)
    assert _period(t, x) == pytest.approx(2 * np.pi * np.sqrt(m / k), rel=0.03)
    assert np.abs(x).max() == pytest.approx(0.5, rel=0.03)  # no growth or decay
    assert contact_count(world) == 0


def test_hanging_spring_equilibrium_and_period():
    """Under gravity a hanging mass oscillates about L0 + m g / k (+-1%) with the same
    period 2 pi sqrt(m / k) (+-3%)."""
    m, k = 1.5, 40.0
    world = p2.World(sleeping=False)
    anchor = world.add(p2.Circle(position=(0.0, 10.0), radius=0.05, fixed=True))
    ball = world.add(p2.Circle(position=(0.0, 8.0), radius=0.2, mass=m))  # released at L0
    world.add(p2.Spring(anchor, ball, rest_length=2.0, stiffness=k))
    t, y = trace(world, 5.0, lambda: ball.position[1])
    stretch = 10.0 - y - 2.0
    centre = 0.5 * (stretch.max() + stretch.min())
    assert centre == pytest.approx(m * G / k, rel=0.01)
    assert stretch.max() == pytest.approx(2 * m * G / k, rel=0.03)  # released at L0
    assert _period(t, stretch) == pytest.approx(2 * np.pi * np.sqrt(m / k), rel=0.03)


@pytest.mark.parametrize(("m", "k"), [(1.0, 50.0), (2.0, 20.0)])
def test_undamped_spring_energy_conserved(m, k):
    """k (L - L0)^2 / 2 + m v^2 / 2 is constant: within 3% at every step over 10 periods,
    with no upward trend (first and last period means within 0.5%)."""
    world, _ = _mass_on_spring(m, k)
    period = 2 * np.pi * np.sqrt(m / k)
    start = world.energy()
    assert start.elastic == pytest.approx(0.5 * k * 0.5**2)
    t, energy = trace(world, 10 * period, lambda: world.energy().total)
    relative = energy / start.total
    assert np.abs(relative - 1.0).max() < 0.03
    one = t <= period
    last = t >= t[-1] - period
    assert relative[last].mean() - relative[one].mean() < 0.005
    assert abs(relative[last].mean() - relative[one].mean()) < 0.005
    slope = np.polyfit(t, relative, 1)[0]
    assert abs(slope) * t[-1] < 0.005


@pytest.mark.parametrize(("m", "k", "c"), [(1.0, 50.0, 0.5), (2.0, 20.0, 0.8), (1.0, 100.0, 1.0)])
def test_damped_spring_amplitude_decay_rate(m, k, c):
    """Damping c: peaks decay as exp(-c t / (2 m)); the slope of log(peak) is -c/(2m) (+-5%)."""
    world, ball = _mass_on_spring(m, k, c)
    t, x = trace(world, 8.0, lambda: ball.position[0] - 2.0)
    peaks = np.flatnonzero((x[1:-1] > x[:-2]) & (x[1:-1] >= x[2:])) + 1
    assert peaks.size >= 4
    # Refine each peak with the parabola through its three samples.
    y0, y1, y2 = x[peaks - 1], x[peaks], x[peaks + 1]
    shift = (y0 - y2) / (2 * (y0 - 2 * y1 + y2))
    heights = y1 - 0.25 * (y0 - y2) * shift
    times = t[peaks] + shift * DT
    rate = -np.polyfit(times, np.log(heights), 1)[0]
    assert rate == pytest.approx(c / (2 * m), rel=0.05)


@pytest.mark.parametrize("c", [0.05, 0.5])
def test_damped_spring_energy_never_increases(c):
    """With damping, dE/dt = -c v_along^2 <= 0: the energy averaged over each period falls
    period after period, and ends below exp(-c t / m) E0 + 3%."""
    m, k = 1.0, 50.0
    world, _ = _mass_on_spring(m, k, c)
    period = 2 * np.pi * np.sqrt(m / k)
    start = world.energy().total
    t, energy = trace(world, 8 * period, lambda: world.energy().total)
    means = [energy[(t > i * period) & (t <= (i + 1) * period)].mean() for i in range(8)]
    assert np.all(np.diff(means) < 0.0)
    assert energy[-1] < start * (np.exp(-c * t[-1] / m) + 0.03)


def test_two_free_bodies_on_a_spring():
    """Two free masses on a spring (g = 0): T = 2 pi sqrt(mu / k), mu = m1 m2 / (m1 + m2)
    (+-3%); total momentum and the centre of mass velocity stay exactly constant."""
    m1, m2, k = 1.0, 3.0, 30.0
    world = p2.World(gravity=ZERO_G, sleeping=False)
    a = world.add(p2.Circle(position=(0.0, 0.0), radius=0.2, mass=m1, velocity=(0.5, 0.2)))
    b = world.add(p2.Circle(position=(2.6, 0.0), radius=0.2, mass=m2, velocity=(0.5, 0.2)))
    world.add(p2.Spring(a, b, rest_length=2.0, stiffness=k))
    momentum = m1 * a.velocity + m2 * b.velocity
    mu = m1 * m2 / (m1 + m2)

    def probe():
        return [*(m1 * a.velocity + m2 * b.velocity), b.position[0] - a.position[0] - 2.0]

    t, values = trace(world, 5.0, probe)
    np.testing.assert_allclose(values[:, :2], np.tile(momentum, (t.size, 1)), atol=1e-9)
    assert _period(t, values[:, 2]) == pytest.approx(2 * np.pi * np.sqrt(mu / k), rel=0.03)
    centre = (m1 * a.position + m2 * b.position) / (m1 + m2)
    np.testing.assert_allclose(
        centre, [2.6 * m2 / (m1 + m2), 0.0] + momentum / 4.0 * t[-1], atol=1e-9
    )


def test_spring_pendulum_energy_steady():
    """A ball swinging and bouncing on a spring under gravity (no damping, no contacts):
    kinetic + gravitational + elastic energy stays within 2% for 10 s, with no trend."""
    world = p2.World(sleeping=False)
    anchor = world.add(p2.Circle(position=(0.0, 5.0), radius=0.05, fixed=True))
    ball = world.add(p2.Circle(position=(1.5, 4.0), radius=0.2, mass=1.0))
    world.add(p2.Spring(anchor, ball, rest_length=1.0, stiffness=40.0))
    start = world.energy().total
    t, energy = trace(world, 10.0, lambda: world.energy().total)
    assert contact_count(world) == 0
    relative = energy / start
    assert np.abs(relative - 1.0).max() < 0.02
    assert abs(relative[t > 9.0].mean() - relative[t <= 1.0].mean()) < 0.005


def test_spring_on_rotating_box_energy_steady():
    """A spring pulling a box off its centre makes it spin (torque r x F): linear +
    rotational + elastic energy stays within 3% over 10 s (g = 0), with no trend."""
    world = p2.World(gravity=ZERO_G, sleeping=False)
    anchor = world.add(p2.Circle(position=(0.0, 0.0), radius=0.05, fixed=True))
    box = world.add(
        p2.Box(position=(3.0, 0.5), width=1.0, height=0.4, angle=0.4, velocity=(0.0, 1.0))
    )
    world.add(p2.Spring(anchor, box, rest_length=2.5, stiffness=20.0, anchor2=(0.4, 0.1)))
    start = world.energy().total
    t, values = trace(
        world, 10.0, lambda: [world.energy().total, world.energy().kinetic_rotational]
    )
    relative = values[:, 0] / start
    assert values[:, 1].max() > 0.05 * start  # it does spin
    assert np.abs(relative - 1.0).max() < 0.03
    assert abs(relative[t > 9.0].mean() - relative[t <= 1.0].mean()) < 0.01
