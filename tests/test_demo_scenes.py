"""The demo scenes (``impulse2d.apps.demo``): every scene runs, and does what it says it shows."""

from __future__ import annotations

import itertools
import math
import re

import numpy as np
import pytest

import impulse2d as p2
from impulse2d.apps import demo
from impulse2d.apps.demo import scenes

G = 9.81
NAMES = list(demo.SCENES)


def _solids(world: p2.World) -> list[p2.Body]:
    """The circles and boxes of a world, in slot order."""
    return [b for b in world.bodies if isinstance(b, p2.Body)]


def _run(scene: demo.Scene, world: p2.World, seconds: float) -> None:
    """Step ``world`` (built from ``scene``) for ``seconds`` at the scene's dt."""
    for _ in range(round(seconds / scene.dt)):
        scene.step(world)


def _state(world: p2.World) -> np.ndarray:
    """Position, angle, velocity and angular velocity of every body, one row each."""
    return np.array(
        [[*b.position, b.angle, *b.velocity, b.angular_velocity] for b in _solids(world)]
    )


# -- the registry ----------------------------------------------------------------------------


def test_names_and_descriptions_are_unique_and_well_formed():
    """Names are short lowercase-hyphenated and unique, descriptions one non-empty line each,
    the dict keys are the scenes' names, and times and views are sensible."""
    assert len(NAMES) == 24
    descriptions = [s.description for s in demo.SCENES.values()]
    assert len(set(descriptions)) == len(descriptions)
    for name, scene in demo.SCENES.items():
        assert scene.name == name
        assert re.fullmatch(r"[a-z0-9]+(-[a-z0-9]+)*", name) and len(name) <= 24
        assert scene.description.strip() and "\n" not in scene.description
        assert scene.dt > 0 and 3.0 <= scene.seconds <= 8.0
        assert scene.steps == round(scene.seconds / scene.dt)
        if scene.view is not None:
            xmin, ymin, xmax, ymax = scene.view
            assert xmax > xmin and ymax > ymin
        assert scene.build.__doc__, f"{name}'s builder has no docstring"
    milestones = [n for n in NAMES if n.startswith("m")]
    assert [n[:3] for n in milestones] == [f"m{i:02d}" for i in range(1, 13)]


def test_get_returns_the_scene_and_refuses_unknown_names():
    """``get`` finds a scene by name; an unknown name is a ValueError naming it and listing
    the valid ones."""
    assert demo.get("pyramid") is demo.SCENES["pyramid"]
    with pytest.raises(ValueError, match="no-such-scene") as error:
        demo.get("no-such-scene")
    assert all(name in str(error.value) for name in NAMES)


def test_scene_is_frozen():
    """A Scene cannot be changed after it is made."""
    with pytest.raises(AttributeError):
        demo.SCENES["pyramid"].seconds = 1.0  # type: ignore[misc]


# -- every scene runs --------------------------------------------------------------------------


@pytest.mark.parametrize("name", NAMES)
def test_scene_builds_and_steps_finite(name):
    """Each scene builds a fresh world and steps for its seconds (at most 2 s here) with every
    body's state and the energy finite."""
    scene = demo.get(name)
    world = scene.build()
    assert isinstance(world, p2.World) and _solids(world)
    assert scene.build() is not world
    _run(scene, world, min(scene.seconds, 2.0))
    state = _state(world)
    assert np.isfinite(state).all(), f"{name}: non-finite body state"
    e = world.energy()
    assert np.isfinite([e.kinetic_linear, e.kinetic_rotational, e.potential, e.elastic]).all()


@pytest.mark.parametrize("name", ["m04-all-pairs", "m06-circle-and-box", "contact-forces"])
def test_seeded_scenes_are_deterministic(name):
    """Scenes with randomness draw from a seeded generator: built twice, they step bitwise
    the same."""
    scene = demo.get(name)
    a, b = scene.build(), scene.build()
    _run(scene, a, 0.5)
    _run(scene, b, 0.5)
    assert np.array_equal(_state(a), _state(b))


# -- what the scenes claim ---------------------------------------------------------------------


def test_m01_constant_velocity():
    """With nothing acting, x = x0 + v t."""
    scene = demo.get("m01-constant-velocity")
    world = scene.build()
    start = _state(world)
    _run(scene, world, scene.seconds)
    end = _state(world)
    t = world.time
    np.testing.assert_allclose(end[:, :2], start[:, :2] + start[:, 3:5] * t, atol=1e-12)
    np.testing.assert_array_equal(end[:, 3:], start[:, 3:])


def test_m02_balls_rise_and_fall_together():
    """Both balls are at the same height at every step while in flight, following
    y = v t - g t^2 / 2 (to the integrator's O(dt) error); the sideways one keeps vx."""
    scene = demo.get("m02-gravity")
    world = scene.build()
    up, sideways = _solids(world)
    for _ in range(round(1.5 / scene.dt)):
        scene.step(world)
        t = world.time
        assert up.position[1] == pytest.approx(sideways.position[1], abs=1e-12)
        assert up.position[1] == pytest.approx(8.0 * t - G * t * t / 2, abs=G * t * scene.dt)
        assert sideways.velocity[0] == pytest.approx(2.5, abs=1e-12)


def test_m03_ball_rolls_across_while_boxes_rest():
    """The ball reaches the 20 degree slope; the boxes on both slopes stay where they are."""
    scene = demo.get("m03-plane")
    world = scene.build()
    ball, *boxes = _solids(world)
    start = [b.position for b in boxes]
    furthest = -np.inf
    for _ in range(round(4.0 / scene.dt)):
        scene.step(world)
        furthest = max(furthest, ball.position[0])
    assert furthest > 2.5
    for box, where in zip(boxes, start, strict=True):
        assert np.linalg.norm(box.position - where) < 0.05


def test_m04_bodies_stay_in_the_arena():
    """Every body stays inside the walls (nothing tunnels out) while they keep moving."""
    scene = demo.get("m04-all-pairs")
    world = scene.build()
    hx, hy = scenes.ARENA
    for _ in range(round(4.0 / scene.dt)):
        scene.step(world)
        positions = np.array([b.position for b in _solids(world)])
        assert (np.abs(positions[:, 0]) < hx).all() and (np.abs(positions[:, 1]) < hy).all()
    assert world.energy().kinetic > 10.0


def test_m05_bounce_heights_ordered_by_restitution():
    """Each ball's first rebound peaks at about e^2 of its drop height, so the three are in
    the order of their restitution."""
    scene = demo.get("m05-circle-plane")
    world = scene.build()
    balls = _solids(world)
    bounced = [False] * 3
    apex = [0.0] * 3
    for _ in range(round(2.5 / scene.dt)):
        scene.step(world)
        for i, ball in enumerate(balls):
            vy, bottom = ball.velocity[1], ball.position[1] - ball.radius
            bounced[i] |= vy > 0.0
            if bounced[i]:
                apex[i] = max(apex[i], bottom)
    assert apex[0] < apex[1] < apex[2]
    for e, height in zip(scenes.RESTITUTIONS, apex, strict=True):
        assert height == pytest.approx(e * e * scenes.DROP_HEIGHT, rel=0.1, abs=0.02)


def test_m07_spin_is_constant_and_the_push_turns_the_box():
    """The spinning boxes keep their angular velocity exactly; the box pushed off centre for
    ten steps gets v = F t / m and a clockwise spin of about r x F t / I."""
    scene = demo.get("m07-rotation")
    world = scene.build()
    *spinners, pushed = _solids(world)
    _run(scene, world, 2.0)
    for box, spin in zip(spinners, scenes.SPINS, strict=True):
        assert box.angular_velocity == spin
    push_time = scenes.PUSH_STEPS * scene.dt
    assert pushed.velocity[0] == pytest.approx(scenes.PUSH_FORCE[0] * push_time / pushed.mass)
    assert pushed.velocity[1] == pytest.approx(0.0, abs=1e-3)
    torque = -scenes.PUSH_POINT[1] * scenes.PUSH_FORCE[0]
    assert pushed.angular_velocity == pytest.approx(torque * push_time / pushed.moment, rel=0.05)


def test_m08_boxes_settle_flat():
    """Every box dropped at an angle ends flat on a face (angle a multiple of 90 degrees)."""
    scene = demo.get("m08-box-plane")
    world = scene.build()
    _run(scene, world, scene.seconds)
    for box in _solids(world):
        off = abs((box.angle + math.pi / 4) % (math.pi / 2) - math.pi / 4)
        assert off < 0.01
        assert abs(box.angular_velocity) < 0.01


def test_m09_billiard_collisions():
    """Equal balls head on swap velocities; 4 kg into 1 kg at 2 m/s leaves 1.2 and 3.2 m/s;
    the off-centre equal pair leaves at right angles; kinetic energy is kept."""
    scene = demo.get("m09-circle-circle")
    world = scene.build()
    e0 = world.energy().kinetic
    _run(scene, world, 2.5)
    a, b, heavy, light, c, d = _solids(world)
    np.testing.assert_allclose(a.velocity, (0.0, 0.0), atol=1e-3)
    np.testing.assert_allclose(b.velocity, (2.0, 0.0), atol=1e-3)
    np.testing.assert_allclose(heavy.velocity, (1.2, 0.0), atol=1e-3)
    np.testing.assert_allclose(light.velocity, (3.2, 0.0), atol=1e-3)
    assert np.dot(c.velocity, d.velocity) == pytest.approx(0.0, abs=1e-3)
    assert world.energy().kinetic == pytest.approx(e0, rel=1e-3)


def test_m10_off_centre_hit_spins_the_box():
    """The box hit on its centre line does not turn; the one hit off centre spins clockwise."""
    scene = demo.get("m10-circle-box")
    world = scene.build()
    _run(scene, world, 2.0)
    central, _, off_centre, _ = _solids(world)
    assert central.velocity[0] > 0.5 and abs(central.angular_velocity) < 1e-9
    assert off_centre.velocity[0] > 0.5 and off_centre.angular_velocity < -0.5


def test_m11_column_stands_and_leaning_tower_topples():
    """The straight column's top box stays put; the leaning tower's top box falls."""
    scene = demo.get("m11-box-box")
    world = scene.build()
    boxes = _solids(world)
    column_top, tower_top = boxes[4], boxes[9]
    start = column_top.position
    _run(scene, world, scene.seconds)
    assert np.linalg.norm(column_top.position - start) < 0.01
    assert tower_top.position[1] < 2.0


def test_m12_stopping_distances_and_drag():
    """Each sliding box stops after v^2 / (2 mu g); a ball with drag d falls with speed
    (g / d)(1 - exp(-d t))."""
    scene = demo.get("m12-drag-friction")
    world = scene.build()
    solids = _solids(world)
    sliders = [b for b in solids if isinstance(b, p2.Box) and not b.fixed]
    balls = [b for b in solids if isinstance(b, p2.Circle)]
    start = [b.position[0] for b in sliders]
    _run(scene, world, 0.5)
    for ball, drag in zip(balls, scenes.DRAGS, strict=True):
        t = world.time
        expected = G * t if drag == 0 else G / drag * (1 - math.exp(-drag * t))
        assert -ball.velocity[1] == pytest.approx(expected, rel=0.02)
    _run(scene, world, scene.seconds - 0.5)
    for box, x0, mu in zip(sliders, start, scenes.SLIDE_FRICTIONS, strict=True):
        assert abs(box.velocity[0]) < 1e-3
        assert box.position[0] - x0 == pytest.approx(scenes.SLIDE_SPEED**2 / (2 * mu * G), rel=0.05)


def test_springs_damped_oscillator_dies_out():
    """The damped bob's swing shrinks as exp(-c t / 2m) while the undamped one's does not."""
    scene = demo.get("springs")
    world = scene.build()
    undamped, damped = [s.body2 for s in world.springs[-2:]]
    rest = [b.position[1] for b in (undamped, damped)]  # both start 0.8 m below rest
    _run(scene, world, 4.0 - 1e-9)
    swings = {id(b): 0.0 for b in (undamped, damped)}
    for _ in range(round(2.0 / scene.dt)):  # the largest excursion over the next 2 s
        scene.step(world)
        for b, y0 in zip((undamped, damped), rest, strict=True):
            swings[id(b)] = max(swings[id(b)], abs(b.position[1] - (y0 + 0.8)))
    assert swings[id(undamped)] == pytest.approx(0.8, rel=0.03)
    assert swings[id(damped)] == pytest.approx(0.8 * math.exp(-0.4 * 4.0), rel=0.15)


def test_sleeping_stack_sleeps_then_the_ball_wakes_it():
    """The stack is asleep before the ball arrives (it is still on its shelf at 2.5 s), and
    is awake again once the ball lands on it."""
    scene = demo.get("sleeping")
    world = scene.build()
    solids = _solids(world)
    stack, ball = solids[:4], solids[-1]
    _run(scene, world, 2.5)
    assert not any(b.awake for b in stack)
    assert ball.position[0] < -1.0 and ball.awake
    woke = False
    for _ in range(round(2.0 / scene.dt)):
        scene.step(world)
        woke |= all(b.awake for b in stack)
    assert woke


def test_contact_forces_push_the_overlap_out():
    """30 circles spawned on top of each other end up (nearly) without overlap, inside the
    pit."""
    scene = demo.get("contact-forces")
    world = scene.build()
    _run(scene, world, scene.seconds)
    circles = _solids(world)
    worst = 0.0
    for a, b in itertools.combinations(circles, 2):
        gap = np.linalg.norm(a.position - b.position) - a.radius - b.radius
        worst = max(worst, -gap)
    assert worst < 0.01
    assert all(abs(c.position[0]) < 3.0 and c.position[1] > 0.0 for c in circles)


def test_energy_total_is_kept():
    """Energy moves between kinds (each kind swings by joules) while the total stays within
    1 %."""
    scene = demo.get("energy")
    world = scene.build()
    totals, kinds = [], []
    for _ in range(scene.steps):
        scene.step(world)
        e = world.energy()
        totals.append(e.total)
        kinds.append((e.kinetic_linear, e.kinetic_rotational, e.potential, e.elastic))
    totals, kinds = np.array(totals), np.array(kinds)
    assert np.ptp(totals) < 0.01 * abs(totals[0])
    assert (np.ptp(kinds, axis=0) > 1.0).all()


def test_newtons_cradle_passes_the_motion_to_the_far_ball():
    """After the first impact the far ball leaves with (nearly) the incoming speed while the
    middle three stay (nearly) still."""
    scene = demo.get("newtons-cradle")
    world = scene.build()
    balls = [b for b in _solids(world) if not b.fixed]
    incoming = 0.0
    for _ in range(round(0.8 / scene.dt)):
        scene.step(world)
        incoming = max(incoming, balls[0].velocity[0])
        if balls[4].velocity[0] > 0.9 * incoming > 0.0:
            break
    assert incoming > 1.0
    assert balls[4].velocity[0] > 0.9 * incoming
    assert all(abs(b.velocity[0]) < 0.05 * incoming for b in balls[1:4])
    assert abs(balls[0].velocity[0]) < 0.05 * incoming


def test_pyramid_stands_and_sleeps():
    """No box of the pyramid moves more than 2 cm; it is asleep at the end."""
    scene = demo.get("pyramid")
    world = scene.build()
    start = _state(world)[:, :2]
    _run(scene, world, scene.seconds)
    assert np.abs(_state(world)[:, :2] - start).max() < 0.02
    assert not any(b.awake for b in _solids(world) if not b.fixed)


def test_pool_break_balls_stay_on_the_table_and_energy_only_drops():
    """No ball leaves the table; kinetic energy never rises above the cue ball's."""
    scene = demo.get("pool-break")
    world = scene.build()
    balls = [b for b in _solids(world) if not b.fixed]
    e0 = world.energy().kinetic
    half_x, half_y = scenes.POOL_TABLE[0] / 2, scenes.POOL_TABLE[1] / 2
    for _ in range(round(2.0 / scene.dt)):
        scene.step(world)
        positions = np.array([b.position for b in balls])
        assert (np.abs(positions[:, 0]) < half_x).all()
        assert (np.abs(positions[:, 1]) < half_y).all()
        assert world.energy().kinetic <= e0 * (1 + 1e-9)
    moved = sum(np.linalg.norm(b.velocity) > 0.05 for b in balls[1:])
    assert moved >= 10


def test_slingshot_knocks_the_pig_off():
    """The launched ball brings the top of the tower down: the pig ends on the ground."""
    scene = demo.get("slingshot")
    world = scene.build()
    pig = _solids(world)[-2]
    _run(scene, world, scene.seconds)
    assert pig.position[1] < 0.5


def _ran(name: str) -> p2.World:
    scene = demo.get(name)
    world = scene.build()
    for _ in range(scene.steps):
        scene.step(world)
    return world


def test_polygon_pile_comes_to_rest_above_the_ground():
    world = _ran("polygon-pile")
    movers = [b for b in world.bodies if isinstance(b, (p2.Polygon, p2.Capsule))]
    assert len(movers) == 40
    assert max(float(np.hypot(*b.velocity)) for b in movers) < 0.05
    assert min(float(b.position[1]) for b in movers) > 0.0


def test_pendulum_chain_keeps_its_links_pinned_and_gains_no_energy():
    """Every joint holds its two anchors within 1 cm, and the chain's energy never grows
    past its start (1 %; it loses some where the folding chain strikes itself)."""
    scene = demo.get("pendulum-chain")
    world = scene.build()
    start = world.energy().total
    highest = start
    for _ in range(scene.steps):
        scene.step(world)
        highest = max(highest, world.energy().total)
    for joint in world.joints:
        gap = np.atleast_2d(joint.body2.to_world(_anchor(joint, 2))) - np.atleast_2d(
            joint.body1.to_world(_anchor(joint, 1))
        )
        assert float(np.hypot(*gap[0])) < 0.01
    assert highest - start < 0.01 * (start - _lowest_energy(world))


def _anchor(joint, end: int) -> np.ndarray:
    row = joint.world.state.spring[0, joint.slot]
    return row[0:2] if end == 1 else row[2:4]


def _lowest_energy(world: p2.World) -> float:
    """The chain's energy hanging straight down at rest: its potential then."""
    links = [b for b in world.bodies if isinstance(b, p2.Capsule)]
    return sum(
        -b.mass * 9.81 * (0.5 * 0.5 * (2 * k + 1)) + b.mass * 9.81 * 6.0
        for k, b in enumerate(links)
    )


def test_ragdolls_tumble_down_the_stairs_within_their_joint_limits():
    world = _ran("ragdolls")
    for joint in world.joints:
        assert joint.lower_angle - 0.1 <= float(joint.angle) <= joint.upper_angle + 0.1
    limbs = [b for b in world.bodies if isinstance(b, (p2.Capsule, p2.Circle)) and not b.fixed]
    assert np.mean([float(b.position[0]) for b in limbs]) > 2.0


def test_the_car_climbs_over_the_hill_upright():
    world = _ran("car-hill")
    car = next(b for b in world.bodies if isinstance(b, p2.Polygon))
    assert float(car.position[0]) > 11.0
    assert abs(float(car.angle)) < 1.0
