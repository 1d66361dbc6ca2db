"""Refused steps: the envelope's edge, and calls that change nothing when refused.

``refusal.leaves_envelope`` and the undo rows alone on hand-built states, then through
``World``: a scene that pumps energy until it leaves the envelope is refused by name and
never reaches NaN, and a refusal in any world of a batch (a spring too stiff, a world
out of the envelope), after any number of steps, on one or two threads, leaves every
world bitwise as it was before the call. The random scenes of the ``edge`` family
(``scene_laws``) check the same over many scenes.
"""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import HealthCheck, given, note, settings

import impulse2d as p2
import scenes_random as sr
from impulse2d import envelope
from impulse2d.core import refusal
from impulse2d.core.state import CONTACT_COUNT, MASS, OMEGA, SLEEP_TIME, VX, VY, X, Y

DT = 1 / 60


def _same(world: p2.World, snapshot: p2.Snapshot) -> bool:
    saved = snapshot.state.arrays()
    return all(np.array_equal(a, saved[name]) for name, a in world.state.arrays().items())


def _pump(batch: int = 1, restitution=2.0, threads: int = 1) -> tuple[p2.World, p2.Circle]:
    """A ball between two planes 2 m apart, no gravity, 10 m/s at the start, bouncing at
    its own ``restitution`` (per world if an array; the world mixes by the larger): at 2
    its speed doubles at each bounce."""
    world = p2.World(gravity=(0.0, 0.0), batch_size=batch, threads=threads)
    world.add(p2.Plane(normal=(0, 1), point=(0, -1), restitution=0.0))
    world.add(p2.Plane(normal=(0, -1), point=(0, 1), restitution=0.0))
    ball = world.add(p2.Circle(radius=0.25, velocity=(0, 10), restitution=1.0))
    ball.restitution = restitution
    return world, ball


# -- the stages alone --------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("column", "value", "what"),
    [
        (VX, 0.99 * envelope.SPEED, None),
        (VY, 1.01 * envelope.SPEED, refusal.SPEED),
        (VX, 0.8 * envelope.SPEED, None),  # with VY below: |v| = 1.13e4 > 1e4
        (OMEGA, -1.01 * envelope.ANGULAR_SPEED, refusal.ANGULAR_SPEED),
        (X, 1.01 * envelope.COORDINATE, refusal.POSITION),
        (Y, -1.01 * envelope.COORDINATE, refusal.POSITION),
        (VX, float("nan"), refusal.NOT_FINITE),
        (OMEGA, float("inf"), refusal.ANGULAR_SPEED),
        (Y, float("nan"), refusal.NOT_FINITE),
    ],
)
def test_leaves_envelope_names_the_body_and_the_quantity(column, value, what) -> None:
    """Two worlds, a plane and two balls; one value of ball 2 in world 1 set by hand. The
    check finds that ball and what is outside; world 0 and values inside pass."""
    world = p2.World(batch_size=2)
    world.add(p2.Plane())
    world.add(p2.Circle(position=(0, 1)))
    world.add(p2.Circle(position=(2, 1)))
    body, body_i, shapes = world.state.body, world.state.body_i, world.layout.shapes
    body[1, 2, column] = value
    if column == VX and what is None and value < 0.9 * envelope.SPEED:
        body[1, 2, VY] = 0.8 * envelope.SPEED  # each component inside, the speed not
        what = refusal.SPEED
    assert refusal.leaves_envelope(body, body_i, shapes, 0) == (-1, -1)
    expected = (-1, -1) if what is None else (2, what)
    assert refusal.leaves_envelope(body, body_i, shapes, 1) == expected


def test_a_planes_and_a_switched_off_body_are_not_checked() -> None:
    world = p2.World()
    plane = world.add(p2.Plane())
    ball = world.add(p2.Circle(position=(0, 1)))
    world.state.body[0, ball.slot, VX] = 2 * envelope.SPEED
    ball.enabled = False
    world.state.body[0, plane.slot, X] = 2 * envelope.COORDINATE  # a plane's point: not a body
    state, shapes = world.state, world.layout.shapes
    assert refusal.leaves_envelope(state.body, state.body_i, shapes, 0) == (-1, -1)


def test_save_then_restore_puts_a_world_back_bitwise() -> None:
    """World 1 of two saved mid-scene (contacts in its cache), both stepped 30 times,
    world 1 restored: it is bitwise as saved; world 0 keeps its steps."""
    world = p2.World(batch_size=2)
    world.add(p2.Plane())
    for i in range(4):
        world.add(p2.Box(position=(0.3 * i, 0.5 + 1.1 * i), angle=0.2 * i))
    world.step(DT, steps=40)
    assert world.contacts().size > 0
    saved = world.snapshot()
    state = world.state
    floats, ints = refusal.undo_sizes(
        state.body.shape[1], state.contact_capacity, state.spring.shape[1]
    )
    undo = np.full((2, floats), -7.0), np.full((2, ints), -7, np.int64)
    refusal.save_world(tuple(state.arrays().values()), world.layout.shapes, *undo, 1)
    world.step(DT, steps=30)
    stepped = np.array([1])
    refusal.restore(*world.state.arrays().values(), world.layout.rows, *undo, stepped)
    for name, array in world.state.arrays().items():
        np.testing.assert_array_equal(array[1], saved.state.arrays()[name][1], err_msg=name)
    assert world.state.time[0] == pytest.approx(70 * DT)


@settings(
    max_examples=40, deadline=None, derandomize=True, database=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)  # fmt: skip
@given(scene=sr.scenes())
def test_a_step_changes_only_what_the_undo_saves(scene) -> None:
    """Over random scenes (every kind of body, planes, springs, sleeping), 40 steps: the
    body columns the undo does not save (``MASS`` to ``ROLLING``) never change, and the
    contact rows past the count stay zero, so saving the rest is saving the world."""
    note(sr.code(scene))
    world = sr.build(scene)
    cold = world.state.body[..., MASS:SLEEP_TIME].copy()
    for _ in range(40):
        world.step(scene.dt)
        count = int(world.state.world_i[0, CONTACT_COUNT])
        assert not world.state.contact[0, count:].any()
        assert not world.state.contact_i[0, count:].any()
    np.testing.assert_array_equal(world.state.body[..., MASS:SLEEP_TIME], cold)


# -- the edge: energy pumped in until the scene leaves -----------------------------------------
def test_a_scene_that_pumps_energy_is_refused_at_the_edge_never_nan() -> None:
    """Restitution 2 doubles the ball's speed at every bounce: every step that goes
    through leaves a finite state inside the envelope; the step that would take the ball
    past 1e4 m/s raises ``EnvelopeError`` naming the body and the quantity, and leaves
    the world bitwise as it was, so that the next try refuses the same way."""
    world, ball = _pump()
    steps = 0
    while True:
        before = world.snapshot()
        try:
            world.step(DT)
        except p2.EnvelopeError as error:
            refused = error
            break
        steps += 1
        speed = float(np.hypot(*ball.velocity))
        assert np.isfinite(world.state.body[0, ball.slot, :6]).all() and speed <= envelope.SPEED
        assert steps < 2000, "the scene never left the envelope"
    assert (refused.world, refused.body, refused.quantity) == (0, ball.slot, "speed")
    assert isinstance(refused, ValueError)
    message = str(refused)
    for words in ("Circle slot 2", "speed passed 10000 m/s", "impulse2d.envelope", "refused"):
        assert words in message
    assert _same(world, before)
    assert float(np.hypot(*ball.velocity)) > 0.25 * envelope.SPEED  # it was near the edge
    with pytest.raises(p2.EnvelopeError, match="speed passed") as again:
        world.step(DT)
    assert str(again.value) == message and _same(world, before)


def test_a_body_that_flies_beyond_the_coordinate_range_is_refused() -> None:
    """9 km/s with nothing in the way: past 1e6 m after 112 steps of 1 s, in one call of
    200 steps. The call is refused and the world is at time 0 as before it."""
    world = p2.World(gravity=(0.0, 0.0))
    ball = world.add(p2.Circle(velocity=(9000.0, 0.0)))
    before = world.snapshot()
    with pytest.raises(p2.EnvelopeError, match="step 112 of this call") as refused:
        world.step(1.0, steps=200)
    assert refused.value.quantity == "position" and refused.value.body == ball.slot
    assert _same(world, before) and world.state.time[0] == 0.0


# -- atomic calls ------------------------------------------------------------------------------
@pytest.mark.parametrize("threads", [1, 2])
@pytest.mark.parametrize("steps", [1, 5])
def test_a_refused_spring_in_one_world_leaves_every_world_as_it_was(threads, steps) -> None:
    """Three worlds; world 1's spring too stiff for the substep. Worlds 0 and 2 would
    step; the call is refused, and no world moved: time 0 everywhere, every array
    bitwise as before."""
    if threads > p2.World().threads and threads > 1:
        pytest.skip("one core")
    world = p2.World(gravity=(0.0, -9.81), batch_size=3, threads=threads)
    a = world.add(p2.Circle(position=(0, 0), radius=0.2))
    b = world.add(p2.Circle(position=(1, 0), radius=0.2))
    world.add(p2.Spring(a, b, stiffness=np.array([10.0, 1e7, 10.0])))
    before = world.snapshot()
    with pytest.raises(ValueError, match=r"unstable .* in world 1.*No world stepped"):
        world.step(DT, steps=steps)
    assert _same(world, before)
    assert list(world.state.time) == [0.0, 0.0, 0.0]


@pytest.mark.parametrize("threads", [1, 2])
def test_one_world_leaving_the_envelope_undoes_the_whole_call(threads) -> None:
    """Three worlds of one ball; only world 2 bounces at restitution 2. A call of 200
    steps: world 2 leaves at its 21st step, after worlds 0 and 1 went further; the
    error names world 2, and every world is back as it was before the call."""
    world, _ = _pump(3, np.array([0.5, 1.0, 2.0]), threads=min(threads, p2.World().threads))
    world.step(DT)
    before = world.snapshot()
    with pytest.raises(p2.EnvelopeError, match="world 2, ") as refused:
        world.step(DT, steps=200)
    assert refused.value.world == 2
    assert _same(world, before)
    world.step(DT, steps=10)  # and the worlds step on from there
    assert world.state.time == pytest.approx(np.full(3, 11 * DT))


def test_run_until_rest_with_frames_undoes_the_whole_call() -> None:
    """With a callback the run goes in chunks, frames in between; a refusal in a later
    chunk still leaves the worlds as before the call (the frames were shown)."""
    world, _ = _pump(2, np.array([1.0, 2.0]))
    before = world.snapshot()
    frames = []
    with pytest.raises(p2.EnvelopeError, match="world 1, "):
        world.run_until_rest(DT, 500, every=4, callback=frames.append)
    assert len(frames) >= 2 and _same(world, before)


def test_a_refusal_after_the_contact_rows_grew_restores_their_capacity() -> None:
    """Twelve boxes resting on a floor need more contact rows than a new world holds, so
    the call grows them at its first step; the pumping ball of world 1 is refused later
    in the same call, and the arrays are cut back to the rows they had."""
    world, _ = _pump(2, np.array([1.0, 2.0]))
    for i in range(12):
        world.add(p2.Box(position=(3.0 + 1.2 * i, -0.5), width=1.0, height=1.0))
    capacity = world.state.contact_capacity
    before = world.snapshot()
    with pytest.raises(p2.EnvelopeError, match="world 1, "):
        world.step(DT, steps=100)
    assert _same(world, before) and world.state.contact_capacity == capacity
    world.step(DT)
    assert world.state.contact_capacity > capacity  # the rows were needed


_PUMP_SCRIPT = """
import hashlib, sys
import numpy as np
import impulse2d as p2
sys.path.insert(0, sys.argv[1])
from test_refusals import _pump
world, _ = _pump(2, np.array([1.0, 2.0]))
try:
    world.step(1 / 60, steps=100)
except p2.EnvelopeError as error:
    digest = hashlib.sha256(b"".join(a.tobytes() for a in world.state.arrays().values()))
    print(error.world, error.body, error.quantity, str(error).split(":")[0], digest.hexdigest())
"""


def test_the_refusal_runs_the_same_without_the_compiler() -> None:
    """The envelope check and the undo are plain Python too: with ``NUMBA_DISABLE_JIT=1``
    the same call is refused at the same step, and the state left is bitwise the same."""
    tests = os.path.dirname(__file__)
    outputs = []
    for disabled in ("0", "1"):
        env = {**os.environ, "NUMBA_DISABLE_JIT": disabled, "IMPULSE2D_QUIET": "1"}
        done = subprocess.run(
            [sys.executable, "-c", _PUMP_SCRIPT, tests],
            env=env, capture_output=True, text=True, timeout=600, check=True,
        )  # fmt: skip
        outputs.append(done.stdout.strip())
    assert outputs[0] == outputs[1] and outputs[0].startswith("1 2 speed world 1, <Circle")
