"""Robustness laws: fast bodies do not tunnel through thin walls or planes, and a heavily
overlapping start resolves without exploding."""

from __future__ import annotations

import functools

import numpy as np
import pytest

import impulse2d as p2
from conftest import DT, run

WALL_HALF = 0.05  # the wall is a fixed box 0.1 m thick, centred on x = 0


def _shoot(body: p2.Body, gravity=(0.0, 0.0), seconds: float = 1.0) -> tuple[float, p2.Body]:
    """Fire ``body`` at a fixed 0.1 m x 2 m wall; return the largest x its centre reached."""
    world = p2.World(gravity=gravity, sleeping=False)
    world.add(p2.Box(position=(0.0, 0.0), width=2 * WALL_HALF, height=2.0, fixed=True))
    body = world.add(body)
    reached = -np.inf
    for _ in range(round(seconds / DT)):
        world.step(DT)
        reached = max(reached, body.position[0])
    return reached, body


@pytest.mark.parametrize("speed", [40.0, 50.0, 100.0])
@pytest.mark.parametrize("radius", [0.05, 0.1])
def test_fast_ball_does_not_pass_thin_wall(radius, speed):
    """Continuous collision: a ball (0.1 or 0.2 m across) at 40-100 m/s, dt = 1/60 (it moves
    7-17 wall thicknesses per step), stops at the near face (x <= -0.05 - r + 1 cm) and stays
    on the near side, whatever the phase of its arrival."""
    for start in np.linspace(-3.0, -3.0 + speed * DT, 6, endpoint=False):
        ball = p2.Circle(position=(start, 0.0), radius=radius, velocity=(speed, 0.0))
        reached, ball = _shoot(ball)
        assert reached <= -WALL_HALF - radius + 0.01, f"start {start}"
        assert ball.position[0] < -WALL_HALF


@pytest.mark.parametrize("restitution", [0.0, 0.8])
def test_fast_ball_at_an_angle_bounces_off_thin_wall(restitution):
    """With gravity and an oblique 40 m/s shot, a 0.1 m ball never crosses the wall."""
    for start in np.linspace(-3.0, -2.4, 6):
        ball = p2.Circle(
            position=(start, 0.5), radius=0.05, velocity=(40.0, -8.0), restitution=restitution
        )
        reached, ball = _shoot(ball, gravity=(0.0, -9.81), seconds=0.5)
        assert reached <= -WALL_HALF - 0.05 + 0.01
        assert ball.position[0] < -WALL_HALF


@pytest.mark.parametrize("spin", [0.0, 30.0])
def test_fast_small_box_does_not_pass_thin_wall(spin):
    """A 0.1 m box at 40 m/s (spinning or not) never gets its centre past the wall."""
    for start in np.linspace(-3.0, -3.0 + 40.0 * DT, 6, endpoint=False):
        box = p2.Box(
            position=(start, 0.1),
            width=0.1,
            height=0.1,
            velocity=(40.0, 0.0),
            angular_velocity=spin,
        )
        reached, box = _shoot(box)
        assert reached < -WALL_HALF
        assert box.position[0] < -WALL_HALF


def _support(body: p2.Body, normal: np.ndarray) -> float:
    """How far the body reaches from its centre along -normal (its half-extent)."""
    if isinstance(body, p2.Circle):
        return float(body.radius)
    c, s = np.cos(body.angle), np.sin(body.angle)
    local = np.array([c * normal[0] + s * normal[1], -s * normal[0] + c * normal[1]])
    return float(abs(local[0]) * body.width / 2 + abs(local[1]) * body.height / 2)


SEEDS = range(6)


@functools.cache
def _plane_scene(seed: int) -> dict[str, float]:
    """Random fast circles and boxes (5-50 m/s, spinning up to 20 rad/s, gravity on) in a
    V of three planes for 3 s. Returns the worst plane distances and penetrations seen after
    any step (per kind) and at the end."""
    rng = np.random.default_rng(seed)
    world = p2.World(sleeping=False)
    planes = [
        world.add(p2.Plane(normal=(0.0, 1.0), point=(0.0, 0.0))),
        world.add(p2.Plane(normal=(1.0, 0.3), point=(-6.0, 0.0))),
        world.add(p2.Plane(normal=(-1.0, 0.3), point=(6.0, 0.0))),
    ]
    bodies = []
    for i in range(40):
        speed, heading = rng.uniform(5.0, 50.0), rng.uniform(0.0, 2 * np.pi)
        kwargs = dict(
            position=(rng.uniform(-4.0, 4.0), rng.uniform(1.0, 8.0)),
            velocity=(speed * np.cos(heading), speed * np.sin(heading)),
            angle=rng.uniform(0.0, 6.0),
            angular_velocity=rng.uniform(-20.0, 20.0),
            restitution=rng.uniform(0.0, 0.9),
            friction=rng.uniform(0.0, 1.0),
        )
        if i % 2:
            bodies.append(world.add(p2.Circle(radius=rng.uniform(0.05, 0.4), **kwargs)))
        else:
            size = dict(width=rng.uniform(0.1, 0.8), height=rng.uniform(0.1, 0.8))
            bodies.append(world.add(p2.Box(**size, **kwargs)))
    worst = dict.fromkeys(["circle_distance", "box_distance"], np.inf)
    worst |= dict.fromkeys(["circle_depth", "box_depth"], 0.0)

    def measure() -> tuple[float, float]:
        closest, deepest = np.inf, 0.0
        for plane in planes:
            normal, point = plane.normal, np.asarray(plane.point)
            for body in bodies:
                kind = "circle" if isinstance(body, p2.Circle) else "box"
                distance = float((body.position - point) @ normal)
                depth = _support(body, normal) - distance
                worst[kind + "_distance"] = min(worst[kind + "_distance"], distance)
                worst[kind + "_depth"] = max(worst[kind + "_depth"], depth)
                closest, deepest = min(closest, distance), max(deepest, depth)
        return closest, deepest

    for _ in range(180):
        world.step(DT)
        closest, deepest = measure()
    worst["end_distance"], worst["end_depth"] = closest, deepest
    return worst


@pytest.mark.parametrize("seed", SEEDS)
def test_fast_bodies_end_in_front_of_planes(seed):
    """Random fast circles and boxes in a V of planes: circles' centres stay in front of
    every plane after every step and sink < 3 cm; at the end nothing is behind a plane
    and nothing sinks more than 1 cm."""
    worst = _plane_scene(seed)
    assert worst["circle_distance"] > 0.0
    assert worst["circle_depth"] < 0.03
    assert worst["end_distance"] > 0.0
    assert worst["end_depth"] < 0.01


def test_fast_boxes_never_cross_a_plane_any_step():
    """Same scenes: after EVERY step every box centre is in front of every plane (distance
    > 0) and no box sinks more than 5 cm. (Boxes spin at up to 90 rad/s here, 0.4 rad per
    substep, and the solver tracks a contact's separation with the rotation linearised,
    as Box2D does; that allows a few centimetres at such spins.)"""
    bad = {}
    for seed in SEEDS:
        worst = _plane_scene(seed)
        if worst["box_distance"] <= 0.0 or worst["box_depth"] >= 0.05:
            bad[seed] = (round(worst["box_distance"], 4), round(worst["box_depth"], 4))
    assert not bad, f"seed: (closest centre distance, deepest penetration) {bad}"


def test_fast_thin_box_landing():
    """A thin box (0.75 x 0.2 m) falling at 40 m/s onto the ground, any phase and angle,
    spinning at 0, 10 or 40 rad/s: its centre stays above the ground and it never sinks
    more than 3 cm."""
    normal = np.array([0.0, 1.0])
    bad = []
    for spin in (0.0, 10.0, 40.0):
        for start in np.linspace(1.0, 1.0 + 40.0 * DT, 4, endpoint=False):
            for angle in np.linspace(0.0, np.pi, 6, endpoint=False):
                world = p2.World(sleeping=False)
                world.add(p2.Plane())
                box = world.add(
                    p2.Box(
                        position=(0.0, start),
                        width=0.75,
                        height=0.2,
                        angle=angle,
                        velocity=(0.0, -40.0),
                        angular_velocity=spin,
                    )
                )
                lowest, deepest = np.inf, 0.0
                for _ in range(30):
                    world.step(DT)
                    lowest = min(lowest, box.position[1])
                    deepest = max(deepest, _support(box, normal) - box.position[1])
                if lowest <= 0.0 or deepest >= 0.03:
                    bad.append((spin, round(start, 3), round(angle, 3), round(deepest, 3)))
    assert not bad, f"(spin, start height, angle, deepest): {bad}"


@pytest.mark.parametrize("ground", [False, True])
def test_overlapping_start_spreads_out(ground):
    """100 circles spawned at one spot push apart (at most contact_push_speed relative)
    without exploding: after 3 s all positions are finite, pairwise overlaps < 1 cm, speeds
    stay moderate (< 20 m/s) and the crowd has spread over several metres."""
    rng = np.random.default_rng(0)
    world = p2.World(gravity=(0.0, -9.81) if ground else (0.0, 0.0), sleeping=False)
    if ground:
        world.add(p2.Plane())
    radius = 0.25
    circles = [
        world.add(
            p2.Circle(position=rng.uniform(-0.01, 0.01, 2) + np.array([0.0, 1.0]), radius=radius)
        )
        for _ in range(100)
    ]
    run(world, 3.0)
    positions = np.array([c.position for c in circles])
    speeds = np.linalg.norm([c.velocity for c in circles], axis=1)
    assert np.all(np.isfinite(positions)) and np.all(np.isfinite(speeds))
    gaps = np.linalg.norm(positions[:, None] - positions[None], axis=-1)
    overlap = 2 * radius - gaps[np.triu_indices(100, 1)]
    assert overlap.max() < 0.01
    assert speeds.max() < 20.0
    assert np.ptp(positions[:, 0]) > 5.0
    if ground:
        assert positions[:, 1].min() > radius - 0.02  # nobody pushed into the ground


def test_millimetre_bodies_thousands_of_sizes_per_step_keep_their_energy():
    """Found by the long fuzz run (``bench/fuzz_scenes.py``, planes family): millimetre
    boxes and a disc at 20-85 m/s between two walls, dt = 0.0645 s with one substep, so
    they move a thousand of their sizes per step and their contacts are made metres
    apart. The state must stay finite and the energy (kinetic + potential, restitution
    <= 0.7) never grow. (It reached 1e189 J and NaN: a friction impulse found while a box
    touched, 4 mm from its centre, was warm-started on the next step onto the same key
    2 m away, where the point's tangent lever arm is 1 m; ``contacts.carry_impulses``.)"""
    world = p2.World(gravity=(0.0, -9.81), substeps=1)
    world.add(
        p2.Box(
            position=(-0.032, -0.033), width=0.0028, height=0.019, angle=-0.32,
            velocity=(-8.0, 84.0), angular_velocity=-6.0, restitution=0.5, friction=0.27,
        )
    )  # fmt: skip
    world.add(
        p2.Box(
            position=(0.008, 0.008), width=0.0018, height=0.008, angle=0.05,
            velocity=(15.0, 3.5), angular_velocity=-8.6, restitution=0.7, friction=0.36,
        )
    )  # fmt: skip
    world.add(
        p2.Circle(position=(-0.002, 0.027), radius=0.0018, velocity=(-22.0, 23.0), friction=0.08)
    )
    world.add(p2.Plane(normal=(1.0, 0.0), point=(-0.28, 0.0), friction=1.0))
    world.add(p2.Plane(normal=(-1.0, 0.0), point=(2.0, 0.0), restitution=0.2, friction=0.76))
    start = world.energy().total
    for step in range(200):
        world.step(0.0645)
        energy = world.energy().total
        assert np.isfinite(energy), f"step {step}"
        assert energy <= 1.01 * start, f"step {step}: {energy:.3g} J of {start:.3g} J"
