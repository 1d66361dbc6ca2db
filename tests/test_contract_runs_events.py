"""The public contract of runs and events: ``World.step(dt, steps)``, ``run_until_rest``,
sensors, health, first contacts and ``contacts()``."""

from __future__ import annotations

import numpy as np
import pytest

import impulse2d as p2
from conftest import DT, names


def _drop(**world):
    """A box dropped onto a ground plane (and a world to drop it in)."""
    w = p2.World(**world)
    w.add(p2.Plane())
    box = w.add(p2.Box(position=(0.0, 1.0), angle=0.3, angular_velocity=2.0))
    return w, box


def test_step_with_steps_is_that_many_steps():
    a, _ = _drop()
    b, _ = _drop()
    for _ in range(200):
        a.step(DT)
    b.step(DT, steps=200)
    assert a.state.body.tobytes() == b.state.body.tobytes()
    assert a.steps == b.steps == 200 and a.time == b.time
    for bad in (0, -1, 1.5, True, "2"):
        with names("steps"):
            b.step(DT, steps=bad)


def test_run_until_rest_stops_each_world_at_rest():
    """Each world steps until it sleeps (or the cap); the steps it took come back, it does
    not move afterwards, and worlds not named do not move at all."""
    w, _ = _drop()
    batch = w.replicate(3)
    batch.bodies[1].position = np.array([[0.0, 1.0], [0.0, 3.0], [0.0, 2.0]])
    before = batch.state.body[2].copy()
    steps = batch.run_until_rest(DT, 2000, worlds=[0, 1])
    assert steps.shape == (2,) and steps.min() > 10 and steps[0] != steps[1]
    assert np.all(batch.at_rest()[:2]) and not batch.at_rest()[2]
    np.testing.assert_array_equal(batch.state.body[2], before)
    np.testing.assert_array_equal(batch.steps, [steps[0], steps[1], 0])
    capped = batch.run_until_rest(DT, 5, worlds=[2])
    assert capped.tolist() == [5]


def test_run_until_rest_equals_steps_and_calls_back_every_k_steps():
    a, _ = _drop()
    b, _ = _drop()
    seen: list[int] = []
    taken = a.run_until_rest(DT, 1000, every=25, callback=lambda s: seen.append(int(s[0])))
    for _ in range(int(taken[0])):
        b.step(DT)
    assert a.state.body.tobytes() == b.state.body.tobytes()
    assert seen == list(range(25, int(taken[0]) + 1, 25))
    with names("callback"):
        a.run_until_rest(DT, 10, callback=3)
    with names("max_steps"):
        a.run_until_rest(DT, 0)
    with names("worlds"):
        a.run_until_rest(DT, 10, worlds=[1])


def test_sensor_reports_and_disables_the_bodies_that_enter():
    """A ball rolling into a circle sensor that disables is switched off there, and its
    ``sensed`` names the sensor; a ball that misses it is untouched."""
    w = p2.World(gravity=(0.0, 0.0))
    pocket = w.add(p2.Sensor(position=(1.0, 0.0), radius=0.1, disables=True))
    w.add(p2.Sensor(position=(0.0, 0.0), width=10.0, height=10.0, outside=True))
    hit = w.add(p2.Circle(position=(0.0, 0.0), radius=0.05, velocity=(2.0, 0.0)))
    miss = w.add(p2.Circle(position=(0.0, 0.5), radius=0.05, velocity=(2.0, 0.0)))
    for _ in range(40):
        w.step(DT)
    assert not hit.enabled and hit.sensed == pocket.slot
    assert 0.9 < hit.position[0] < 1.0  # it stopped where its centre crossed the rim
    assert miss.enabled and miss.sensed == -1
    for _ in range(200):  # out of the 10 m box: reported, not disabled
        w.step(DT)
    assert miss.enabled and miss.sensed == 1
    w.reset_events()
    assert miss.sensed == -1


def test_sensor_arguments_are_checked():
    with names("radius"):
        p2.Sensor(position=(0, 0))
    with names("radius"):
        p2.Sensor(radius=1.0, width=2.0, height=1.0)
    with names("radius"):
        p2.Sensor(radius=-1.0)
    with names("width"):
        p2.Sensor(width=0.0, height=1.0)
    with names("outside"):
        p2.Sensor(radius=1.0, outside="yes")
    sensor = p2.World().add(p2.Sensor(radius=1.0))
    with pytest.raises(AttributeError, match="width"):
        sensor.width = 2.0
    with names("enabled"):
        sensor.enabled = 1


def test_health_is_drained_by_impacts_and_the_body_breaks():
    """A 1 kg ball falling 2 m onto the ground takes about m v (1 + e) = 6.3 N s: with 10
    N s of health it survives with about 3.7; with 5 it breaks (switched off)."""
    for health, survives in ((10.0, True), (5.0, False)):
        w = p2.World(damage_speed=0.5)
        w.add(p2.Plane())
        ball = w.add(p2.Circle(position=(0.0, 2.5), radius=0.5, mass=1.0, health=health))
        for _ in range(60):
            w.step(DT)
        assert ball.enabled == survives
        if survives:
            assert ball.health == pytest.approx(health - np.sqrt(2 * 9.81 * 2.0), rel=0.05)
    with names("health"):
        p2.Circle(health=0.0)
    with names("health"):
        p2.Circle(health=float("nan"))
    assert p2.Circle().health == np.inf


def test_first_contact_records_the_first_body_pushed():
    w = p2.World(gravity=(0.0, 0.0))
    a = w.add(p2.Circle(position=(0.0, 0.0), radius=0.1, velocity=(1.0, 0.0)))
    b = w.add(p2.Circle(position=(0.5, 0.0), radius=0.1))
    c = w.add(p2.Circle(position=(1.0, 0.0), radius=0.1))
    for _ in range(120):
        w.step(DT)
    assert a.first_contact == b.slot and b.first_contact == a.slot and c.first_contact == b.slot
    w.reset_events()
    assert (a.first_contact, b.first_contact) == (-1, -1)


def test_contacts_readout_of_a_resting_ball():
    """A resting ball has one contact point below it, normal from the ball (A) to the
    ground (B), separation about 0, and the normal impulse m g dt."""
    w = p2.World()
    ground = w.add(p2.Plane())
    ball = w.add(p2.Circle(position=(0.0, 0.5), radius=0.5, mass=2.0))
    w.sleeping = False
    for _ in range(120):
        w.step(DT)
    c = w.contacts()
    assert c.size == 1 and (c.slot_a[0], c.slot_b[0]) == (ball.slot, ground.slot)
    np.testing.assert_allclose(c.normal[0], [0.0, -1.0], atol=1e-12)
    np.testing.assert_allclose(c.point[0], [0.0, 0.0], atol=1e-3)
    assert abs(c.separation[0]) < 1e-3
    assert c.impulse[0] == pytest.approx(2.0 * 9.81 * DT, rel=1e-6)
    with names("world"):
        w.contacts(1)
