"""The call an RL loop makes each step, ``World.step(dt)``, through the runner's fast path.

``Runner.step_once`` repeats the last call's compiled entry point with the same arguments
while the state's arrays, the layout and the step context are the same objects. These
tests change each of those between calls (room for more contacts, new bodies, a new
setting, a restored snapshot, a refusal, a pickled copy) and check that a run of calls
a step at a time ends bitwise where one call of as many steps ends: a stale argument
would show as a different state or a crash.
"""

from __future__ import annotations

import pickle

import numpy as np
import pytest

import impulse2d as p2

DT = 1 / 60


def _stack(batch: int = 1) -> p2.World:
    """A floor and a row of boxes dropped onto it: their contact points outgrow a new
    world's contact rows a few steps in, after the fast path has been taken."""
    world = p2.World(batch_size=batch)
    world.add(p2.Plane(normal=(0, 1), point=(0, 0)))
    for i in range(12):
        world.add(p2.Box(position=(1.2 * i, 0.6 + 0.05 * i), width=1.0, height=1.0, angle=0.1))
    return world


def _arrays(world: p2.World) -> dict[str, np.ndarray]:
    return {name: a.copy() for name, a in world.state.arrays().items()}


def _equal(a: dict, b: dict) -> bool:
    return a.keys() == b.keys() and all(np.array_equal(a[k], b[k]) for k in a)


@pytest.mark.parametrize("batch", [1, 3])
def test_a_step_a_call_ends_where_one_call_ends_while_the_contact_rows_grow(batch) -> None:
    calls, one_call = _stack(batch), _stack(batch)
    capacity = calls.state.contact_capacity
    for _ in range(90):
        calls.step(DT)
    one_call.step(DT, steps=90)
    assert calls.state.contact_capacity > capacity  # room was made between fast calls
    assert _equal(_arrays(calls), _arrays(one_call))
    if batch == 1 or calls.threads == 1:  # a batch cut in chunks over threads has no fast path
        assert calls._runner._fast[0] is calls.state  # it was taken again after the growth


def test_bodies_added_between_calls_take_part_in_the_next_step() -> None:
    world = _stack()
    for _ in range(5):
        world.step(DT)
    late = [world.add(p2.Circle(position=(0.5 * i, 5.0), radius=0.2)) for i in range(10)]
    world.step(DT)
    assert all(ball.velocity[1] == pytest.approx(-9.81 * DT) for ball in late)
    world.remove(late[0])
    world.step(DT)
    assert late[0].velocity[1] == pytest.approx(-9.81 * DT)  # out of the world: not stepped
    assert late[1].velocity[1] == pytest.approx(-2 * 9.81 * DT)


def test_a_setting_changed_between_calls_applies_at_the_next_step() -> None:
    world = p2.World(gravity=(0.0, -10.0))
    ball = world.add(p2.Circle(radius=0.5, position=(0, 10)))
    world.step(DT)
    world.step(DT)
    world.gravity = (3.0, 0.0)
    world.step(DT)
    assert ball.velocity == pytest.approx((3.0 * DT, -20.0 * DT))
    world.step(2 * DT)  # a new dt is a new context too
    assert ball.velocity == pytest.approx((9.0 * DT, -20.0 * DT))


def test_a_restored_snapshot_replays_bitwise_on_the_fast_path() -> None:
    world = _stack()
    for _ in range(10):
        world.step(DT)
    snapshot = world.snapshot()
    for _ in range(40):
        world.step(DT)
    first = _arrays(world)
    world.restore(snapshot)
    for _ in range(40):
        world.step(DT)
    assert _equal(_arrays(world), first)


def test_a_refusal_on_the_fast_path_changes_nothing_and_the_world_steps_on() -> None:
    world = p2.World(gravity=(0.0, 0.0))
    a = world.add(p2.Circle(position=(0, 0), radius=0.2))
    b = world.add(p2.Circle(position=(1, 0), radius=0.2, velocity=(1, 0)))
    spring = world.add(p2.Spring(a, b, stiffness=10.0))
    for _ in range(3):
        world.step(DT)
    spring.stiffness = 1e7
    before = _arrays(world)
    with pytest.raises(ValueError, match="unstable"):
        world.step(DT)
    assert _equal(_arrays(world), before)
    spring.stiffness = 10.0
    world.step(DT)
    assert world.time == pytest.approx(4 * DT)


def test_a_pickled_world_steps_as_the_original() -> None:
    world = _stack()
    for _ in range(20):
        world.step(DT)
    twin = pickle.loads(pickle.dumps(world))
    for _ in range(30):
        world.step(DT)
        twin.step(DT)
    assert _equal(_arrays(world), _arrays(twin))


def test_threads_changed_between_calls_keep_the_bits() -> None:
    calls, one_call = _stack(4), _stack(4)
    for k in range(40):
        calls.threads = 1 + k % 2
        calls.step(DT)
    one_call.step(DT, steps=40)
    assert _equal(_arrays(calls), _arrays(one_call))


def test_a_snapshot_with_more_contact_rows_restored_between_calls() -> None:
    """A snapshot of a world built by the same code whose contact rows grew, restored
    into one whose fast path holds its smaller arrays: the next calls use the new ones."""
    grown, fresh = _stack(), _stack()
    grown.step(DT, steps=90)
    fresh.step(DT)
    fresh.step(DT)
    assert fresh.state.contact_capacity < grown.state.contact_capacity
    fresh.restore(grown.snapshot())
    for _ in range(20):
        fresh.step(DT)
    grown.step(DT, steps=20)
    assert _equal(_arrays(fresh), _arrays(grown))
