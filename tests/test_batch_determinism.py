"""Determinism and batching contract: results are bitwise reproducible, and every world of a
batch evolves exactly (np.array_equal, not allclose) as the same world stepped alone.
"""

from __future__ import annotations

import numpy as np
import pytest

import impulse2d as p2

DT = 1.0 / 60.0


# -- helpers ----------------------------------------------------------------------------------
def build_messy(world: p2.World) -> p2.World:
    """Planes, a leaning stack of boxes, bouncing spinning circles, tumbling rotated boxes and
    a spring: every pair kind and the solver's warm starting get exercised."""
    world.add(p2.Plane(normal=(0.0, 1.0), point=(0.0, 0.0), friction=0.6))
    world.add(p2.Plane(normal=(1.0, 0.1), point=(-4.0, 0.0), restitution=0.3))
    world.add(p2.Plane(normal=(-1.0, 0.1), point=(4.0, 0.0)))
    for i in range(4):
        world.add(
            p2.Box(position=(0.3 * (i % 2), 0.5 + 1.01 * i), width=1.0, height=1.0, friction=0.6)
        )
    rng = np.random.default_rng(1)
    for i in range(6):
        world.add(
            p2.Circle(
                position=(-3.0 + 1.1 * i, 6.0 + 0.7 * i),
                radius=0.3 + 0.05 * i,
                mass=0.5 + 0.1 * i,
                velocity=tuple(rng.normal(size=2)),
                angular_velocity=float(rng.normal()),
                restitution=0.7,
                friction=0.4,
            )
        )
    for i in range(3):
        world.add(
            p2.Box(
                position=(2.5 - 1.2 * i, 9.0 + i),
                width=0.8,
                height=0.4,
                angle=0.3 * i + 0.2,
                mass=1.5,
                angular_velocity=1.0 - i,
                restitution=0.2,
            )
        )
    top_box, circle = world.bodies[6], world.bodies[8]
    world.add(
        p2.Spring(top_box, circle, rest_length=2.0, stiffness=20.0, damping=0.5, anchor1=(0.5, 0.5))
    )
    return world


def build_drop(world: p2.World) -> p2.World:
    """A box hanging in the air above a plane with a ball above it (for the enabled mask)."""
    world.add(p2.Plane())
    world.add(p2.Box(position=(0.0, 2.0), width=2.0, height=0.5))
    world.add(p2.Circle(position=(0.0, 4.0), radius=0.4, restitution=0.5))
    world.add(p2.Circle(position=(3.0, 1.0), radius=0.4, velocity=(-1.0, 2.0)))
    return world


def state(world: p2.World, k: int | None = None) -> np.ndarray:
    """Pose and velocity of every circle and box (rows), of world ``k`` of a batch."""
    rows = []
    for body in world.bodies:
        if isinstance(body, p2.Plane):
            continue
        values = [body.position, body.velocity, body.angle, body.angular_velocity]
        if k is not None:
            values = [np.asarray(v)[k] for v in values]
        rows.append(np.concatenate([np.ravel(v) for v in values]))
    return np.array(rows)


def awake(world: p2.World, k: int | None = None) -> np.ndarray:
    flags = [b.awake for b in world.bodies if not isinstance(b, p2.Plane)]
    return np.array(flags if k is None else [f[k] for f in flags])


def run(world: p2.World, n: int) -> list[np.ndarray]:
    out = []
    for _ in range(n):
        world.step(DT)
        out.append(state(world))
    return out


def assert_world_equals_single(batch: p2.World, k: int, single: p2.World) -> None:
    np.testing.assert_array_equal(state(batch, k), state(single), err_msg=f"world {k}")
    np.testing.assert_array_equal(awake(batch, k), awake(single), err_msg=f"awake {k}")


# -- repeatability ------------------------------------------------------------------------------
def test_same_scene_twice_is_bitwise_identical():
    """Building and stepping the same messy scene twice gives bitwise-identical states."""
    first, second = build_messy(p2.World()), build_messy(p2.World())
    for step in range(240):
        first.step(DT)
        second.step(DT)
        if step % 40 == 39:
            np.testing.assert_array_equal(state(first), state(second), err_msg=f"step {step}")
    np.testing.assert_array_equal(state(first), state(second))
    np.testing.assert_array_equal(awake(first), awake(second))
    assert first.energy() == second.energy()
    moved = state(first)[:, :2] - state(build_messy(p2.World()))[:, :2]
    assert np.abs(moved).max() > 1.0, "the scene must actually move for this test to mean much"


def test_snapshot_restore_repeats_bitwise():
    """restore(snapshot) brings back the exact state, and stepping after it repeats bitwise."""
    world = build_messy(p2.World())
    for _ in range(60):
        world.step(DT)
    snap = world.snapshot()
    at_snap, time, count = state(world), world.time, world.steps
    first = run(world, 150)
    world.restore(snap)
    np.testing.assert_array_equal(state(world), at_snap)
    assert world.time == time and world.steps == count
    second = run(world, 150)
    for step, (a, b) in enumerate(zip(first, second, strict=True)):
        np.testing.assert_array_equal(a, b, err_msg=f"step {step} after restore")
    world.restore(snap)  # a snapshot can be restored more than once
    np.testing.assert_array_equal(run(world, 150)[-1], first[-1])


def test_snapshot_is_unaffected_by_later_changes():
    """A snapshot is a copy: later property changes do not alter what it restores."""
    world = build_messy(p2.World())
    for _ in range(30):
        world.step(DT)
    snap = world.snapshot()
    expected = run(world, 60)[-1]
    world.restore(snap)
    for body in world.bodies[3:]:
        body.velocity = (5.0, 5.0)
        body.mass = 9.0
    world.springs[0].stiffness = 1.0
    world.restore(snap)
    np.testing.assert_array_equal(run(world, 60)[-1], expected)


def test_restore_brings_back_the_settings_and_the_last_contacts():
    """Settings changed after a snapshot (gravity, substeps, contact and sleep settings)
    come back with it, so stepping repeats the original run bitwise; and the last step's
    contacts come back, so ``impulses()`` and ``contacts()`` read what they read then."""
    world = build_messy(p2.World())
    for _ in range(40):
        world.step(DT)
    snap = world.snapshot()
    impulses, contacts = world.impulses().copy(), world.contacts()
    assert impulses.any()
    expected = run(world, 60)[-1]
    world.restore(snap)
    np.testing.assert_array_equal(world.impulses(), impulses)
    np.testing.assert_array_equal(world.contacts().point, contacts.point)
    world.gravity, world.substeps = (1.0, -3.0), 2
    world.contact_hertz, world.sleeping, world.restitution_threshold = 5.0, False, 0.1
    changed = run(world, 60)[-1]
    assert not np.array_equal(changed, expected)
    world.restore(snap)
    assert world.substeps == 4 and world.sleeping and world.contact_hertz == 30.0
    np.testing.assert_array_equal(world.gravity, (0.0, -9.81))
    np.testing.assert_array_equal(run(world, 60)[-1], expected)
    world.gravity = (0.0, -1.0)  # a restored world's settings are its own again
    assert snap.settings.gravity[1] == -9.81


# -- batches ---------------------------------------------------------------------------------
@pytest.mark.parametrize("when", [0, 45])
def test_replicate_steps_each_world_like_the_single_world(when):
    """replicate(n), at start or mid-run, steps every world bitwise like the original alone."""
    single = build_messy(p2.World())
    for _ in range(when):
        single.step(DT)
    batch = single.replicate(5)
    for step in range(200):
        single.step(DT)
        batch.step(DT)
        if step % 50 == 49:
            for k in range(5):
                assert_world_equals_single(batch, k, single)
    for k in range(5):
        assert_world_equals_single(batch, k, single)


def test_batch_world_steps_each_world_like_a_single_world():
    """World(batch_size=n) with the same adds steps every world bitwise like a single world."""
    single = build_messy(p2.World())
    batch = build_messy(p2.World(batch_size=4))
    for _ in range(200):
        single.step(DT)
        batch.step(DT)
    for k in range(4):
        assert_world_equals_single(batch, k, single)
    single_energy, batch_energy = single.energy(), batch.energy()
    for field in ("kinetic_linear", "kinetic_rotational", "potential", "elastic"):
        np.testing.assert_array_equal(
            getattr(batch_energy, field), np.full(4, getattr(single_energy, field)), err_msg=field
        )


def test_per_world_settings_evolve_like_single_worlds():
    """Per-world velocities and materials evolve bitwise like single worlds set up the same."""
    count = 4
    rng = np.random.default_rng(5)
    velocities = rng.normal(size=(count, 2)) * 3.0
    spins = np.linspace(-2.0, 2.0, count)
    restitutions = np.array([0.0, 0.3, 0.6, 0.9])
    batch = build_messy(p2.World(batch_size=count))
    batch.bodies[7].velocity = velocities
    batch.bodies[13].angular_velocity = spins
    batch.bodies[9].restitution = restitutions
    singles = []
    for k in range(count):
        single = build_messy(p2.World())
        single.bodies[7].velocity = velocities[k]
        single.bodies[13].angular_velocity = spins[k]
        single.bodies[9].restitution = restitutions[k]
        singles.append(single)
    for _ in range(200):
        batch.step(DT)
        for single in singles:
            single.step(DT)
    for k in range(count):
        assert_world_equals_single(batch, k, singles[k])
    assert not np.array_equal(state(batch, 0), state(batch, 1)), "worlds must differ"


def test_disabled_body_leaves_other_worlds_bitwise_unchanged():
    """Disabling a box in one world leaves the other worlds bitwise like a single world."""
    count = 4
    batch = build_messy(p2.World(batch_size=count))
    single = build_messy(p2.World())
    mask = np.ones(count, dtype=bool)
    mask[2] = False
    batch.bodies[4].enabled = mask
    for _ in range(200):
        batch.step(DT)
        single.step(DT)
    for k in (0, 1, 3):
        assert_world_equals_single(batch, k, single)
    assert not np.array_equal(state(batch, 2), state(single))


def test_disabled_body_does_not_move_or_collide():
    """A disabled body stays put and is fallen through; the other worlds match a single world."""
    batch = build_drop(p2.World(batch_size=3))
    single = build_drop(p2.World())
    platform, ball = batch.bodies[1], batch.bodies[2]
    platform.enabled = np.array([True, False, True])
    start = platform.position[1].copy(), platform.angle[1], platform.velocity[1].copy()
    for _ in range(150):
        batch.step(DT)
        single.step(DT)
    np.testing.assert_array_equal(platform.position[1], start[0])
    assert platform.angle[1] == start[1]
    np.testing.assert_array_equal(platform.velocity[1], start[2])
    assert ball.position[1, 1] == pytest.approx(0.4, abs=0.02)  # on the ground, fell through
    assert ball.position[0, 1] == pytest.approx(0.9, abs=0.02)  # on the platform where enabled
    for k in (0, 2):
        assert_world_equals_single(batch, k, single)
    platform.enabled = True  # switched back on, it takes part again
    assert platform.awake[1]
    for _ in range(5):
        batch.step(DT)
    assert platform.position[1, 1] < start[0][1]


def test_restore_single_snapshot_into_one_world():
    """restore(one-world snap, worlds=[i]) resets only world i, which then repeats bitwise."""
    single = build_messy(p2.World())
    for _ in range(20):
        single.step(DT)
    snap = single.snapshot()
    at_snap = state(single)
    expected = run(single, 120)
    batch, control = single.replicate(4), single.replicate(4)
    rng = np.random.default_rng(3)
    kick = rng.normal(size=(4, 2))
    for world in (batch, control):
        world.bodies[5].velocity = kick
        for _ in range(30):
            world.step(DT)
    batch.restore(snap, worlds=[2])
    np.testing.assert_array_equal(state(batch, 2), at_snap)
    for k in (0, 1, 3):
        np.testing.assert_array_equal(state(batch, k), state(control, k))
    for step in range(120):
        batch.step(DT)
        control.step(DT)
        np.testing.assert_array_equal(state(batch, 2), expected[step], err_msg=f"step {step}")
    for k in (0, 1, 3):
        np.testing.assert_array_equal(state(batch, k), state(control, k), err_msg=f"world {k}")
        np.testing.assert_array_equal(awake(batch, k), awake(control, k), err_msg=f"awake {k}")


def test_restore_one_world_snapshot_into_several_worlds():
    """A one-world snapshot restored into worlds=[1, 3] makes both repeat the snapshot's run."""
    single = build_messy(p2.World())
    snap = single.snapshot()
    expected = run(single, 60)[-1]
    batch = build_messy(p2.World(batch_size=4))
    batch.bodies[6].velocity = [[0.0, 1.0], [2.0, 0.0], [0.0, 3.0], [4.0, 0.0]]
    for _ in range(10):
        batch.step(DT)
    batch.restore(snap, worlds=[1, 3])
    for _ in range(60):
        batch.step(DT)
    np.testing.assert_array_equal(state(batch, 1), expected)
    np.testing.assert_array_equal(state(batch, 3), expected)
    assert not np.array_equal(state(batch, 0), expected)


def test_restore_batch_snapshot_into_selected_worlds():
    """w.restore(w.snapshot(), worlds=[3, 5]) resets worlds 3 and 5 only, to their own state."""
    batch = build_messy(p2.World(batch_size=6))
    batch.bodies[6].velocity = np.arange(12.0).reshape(6, 2) * 0.5
    control = build_messy(p2.World(batch_size=6))
    control.bodies[6].velocity = np.arange(12.0).reshape(6, 2) * 0.5
    for _ in range(20):
        batch.step(DT)
        control.step(DT)
    snap = batch.snapshot()
    saved = [state(batch, k) for k in range(6)]
    for _ in range(30):
        batch.step(DT)
        control.step(DT)
    batch.restore(snap, worlds=[3, 5])
    for k in range(6):
        reference = saved[k] if k in (3, 5) else state(control, k)
        np.testing.assert_array_equal(state(batch, k), reference, err_msg=f"world {k}")


def _resting_pair(world: p2.World) -> tuple[p2.Circle, p2.Circle]:
    """Two touching balls on a frictionless floor, put to sleep."""
    world.add(p2.Plane(normal=(0.0, 1.0), point=(0.0, 0.0)))
    a = world.add(p2.Circle(position=(0.0, 0.5), radius=0.5))
    b = world.add(p2.Circle(position=(1.0, 0.5), radius=0.5))
    world.stop()
    return a, b


def test_restored_sleepers_wake_only_in_their_own_world():
    """Island ids are flat indices: a sleeping island copied into another world (restore
    or replicate) must name that world, so a push in one world wakes no other."""
    template = p2.World()
    _resting_pair(template)
    snap = template.snapshot()
    batch = p2.World(batch_size=3)
    a, _ = _resting_pair(batch)
    batch.restore(snap, worlds=[2])
    a.apply_impulse([[0.0, 0.0], [0.0, 0.0], [1.0, 0.0]])
    batch.step(DT)
    assert batch.at_rest().tolist() == [True, True, False]
    copies = template.replicate(3)
    copies.bodies[1].apply_impulse([[1.0, 0.0], [0.0, 0.0], [0.0, 0.0]])
    copies.step(DT)
    assert copies.at_rest().tolist() == [False, True, True]


def test_writing_one_world_leaves_the_others_asleep():
    """A batch setter writes every world, but only the worlds whose value changes are
    woken and re-queried (a game respotting a ball in one world)."""
    batch = p2.World(batch_size=3)
    a, _ = _resting_pair(batch)
    positions = np.array(a.position)
    positions[1] = (-3.0, 0.5)
    a.position = positions
    assert batch.at_rest().tolist() == [True, False, True]
    assert a.awake.tolist() == [False, True, False]


def test_restore_refreshes_per_world_sizes():
    """A snapshot whose bodies have other sizes than the target world's: after restore the
    broadphase uses the restored sizes, so a pebble dropped on a big ball lands on it."""

    def scene(world: p2.World, big: float) -> p2.Circle:
        world.add(p2.Plane(normal=(0.0, 1.0), point=(0.0, 0.0)))
        world.add(p2.Circle(position=(0.0, big), radius=big))
        return world.add(p2.Circle(position=(0.0, 4.3), radius=0.1))

    template = p2.World()
    pebble = scene(template, 2.0)
    snap = template.snapshot()
    batch = p2.World(batch_size=2)
    pebbles = scene(batch, 0.1)
    batch.restore(snap, worlds=[1])
    for _ in range(90):
        batch.step(DT)
        template.step(DT)
    assert pebble.position[1] == pytest.approx(4.1, abs=0.01)
    np.testing.assert_array_equal(pebbles.position[1], pebble.position)
