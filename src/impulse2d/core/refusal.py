"""Refused steps: a world that leaves the envelope is caught, and a refused call undone.

*The edge.* Inside ``envelope``'s ranges every step gives finite numbers, but a scene
can drive itself out of them: restitution above 1 pumps energy into every bounce, and a
kinematic pusher can squeeze a light body into a wedge of planes faster and faster.
Left alone such a scene reaches 1e7 m/s and then NaN. ``leaves_envelope`` is the last
stage of every step: it finds the first body of the world whose state is outside the
ranges (speed, angular speed, position, or not finite at all), and the step is refused.

*Atomic calls.* A compiled call steps many worlds, each as far as asked, and a world can
be refused after others (or itself) have stepped. So before a world's first step in a
call, ``save_world`` copies what a step can change into the runner's undo rows; when any
world of the call is refused, ``restore`` puts every world that stepped back as it was.
A refused call changes nothing.

What a step can change, and so what is saved: the clock, the world's counters, each
body's pose, velocity, forces, sleep time, health and cached cosines and drag factors
(``body`` columns ``X`` to ``TORQUE`` and ``SLEEP_TIME`` to the end: 16 of 30; the
material and mass columns between them are set only from Python), its integer row, and
the contact rows up to the count (the rows after it are zero, ``state.py``). Float
columns are saved for the slots up to the last one in use, integer rows for every slot
(the broadphase's ``SAP_ORDER`` column orders all of them). Undo rows, one per world of
the batch, laid out for ``N`` body slots and ``C`` contact rows::

    floats (B, 1 + N * SAVED_BODY_F + S * SAVED_SPRING_F + C * CONTACT_F): time, body
        rows, the spring table's rows (what a joint writes: on, impulses, forces),
        contact rows
    ints   (B, WORLD_I + N * BODY_I + C * CONTACT_I): world_i, body_i rows, contact_i rows

Two arrays, ``undo_floats`` and ``undo_ints``, each world's row holding its parts one
after the other. A world that stepped has its undo rows filled at most once per call. If
the call grew the contact arrays (a world needed more room), the runner cuts them back to
``C`` rows before ``restore``.
"""

from __future__ import annotations

from .. import envelope
from ._jit import kernel
from .state import (
    AWAKE,
    BODY_F,
    BODY_I,
    CONTACT_COUNT,
    CONTACT_F,
    CONTACT_I,
    ENABLED,
    FREE,
    IMPULSE_X,
    JOINT_TORQUE,
    OMEGA,
    PLANE,
    SLEEP_TIME,
    SPRING_ON,
    TORQUE,
    VX,
    VY,
    WORLD_I,
    X,
    Y,
)

# What took a world out of the envelope (a refused plan row's BAD_WHAT).
SPEED, ANGULAR_SPEED, POSITION, NOT_FINITE = 0, 1, 2, 3
WHAT = ("speed", "angular speed", "position", "not finite")

_SPEED_SQUARED = envelope.SPEED * envelope.SPEED
# Saved per body: the columns X to TORQUE and SLEEP_TIME to the end.
SAVED_BODY_F = TORQUE + 1 + BODY_F - SLEEP_TIME
_COLD = SLEEP_TIME - (TORQUE + 1)  # the columns between, not saved
# Saved per row of the spring table: SPRING_ON (a joint breaks) and the impulses and forces.
SAVED_SPRING_F = 1 + JOINT_TORQUE + 1 - IMPULSE_X


def undo_sizes(bodies: int, contacts: int, springs: int = 0) -> tuple[int, int]:
    """Lengths of the float and the int part of one world's undo row."""
    floats = 1 + bodies * SAVED_BODY_F + springs * SAVED_SPRING_F + contacts * CONTACT_F
    return floats, WORLD_I + bodies * BODY_I + contacts * CONTACT_I


@kernel
def _slots_in_use(shapes) -> int:
    """One past the last body slot in use (free slots after it never change)."""
    for i in range(shapes.shape[0] - 1, -1, -1):
        if shapes[i, 0] != FREE:
            return i + 1
    return 0


@kernel
def save_world(state, shapes, undo_floats, undo_ints, w) -> None:
    """Copy what a step of world ``w`` can change into its undo rows. (Scalar loops: on
    rows this short, numba's slice copies cost more than the copying.)"""
    body, body_i, spring, _, contact, contact_i, world_i, time, _ = state
    floats, ints = undo_floats[w], undo_ints[w]
    floats[0] = time[w]
    at = 1
    for i in range(_slots_in_use(shapes)):
        for column in range(TORQUE + 1):
            floats[at + column] = body[w, i, column]
        for column in range(SLEEP_TIME, BODY_F):
            floats[at + column - _COLD] = body[w, i, column]
        at += SAVED_BODY_F
    for k in range(spring.shape[1]):
        floats[at] = spring[w, k, SPRING_ON]
        for column in range(IMPULSE_X, JOINT_TORQUE + 1):
            floats[at + 1 + column - IMPULSE_X] = spring[w, k, column]
        at += SAVED_SPRING_F
    for j in range(world_i[w, CONTACT_COUNT]):
        for column in range(CONTACT_F):
            floats[at + column] = contact[w, j, column]
        at += CONTACT_F
    for k in range(WORLD_I):
        ints[k] = world_i[w, k]
    at = WORLD_I
    for i in range(body_i.shape[1]):  # every slot: SAP_ORDER orders them all
        for column in range(BODY_I):
            ints[at + column] = body_i[w, i, column]
        at += BODY_I
    for j in range(world_i[w, CONTACT_COUNT]):
        for column in range(CONTACT_I):
            ints[at + column] = contact_i[w, j, column]
        at += CONTACT_I


@kernel
def restore_world(state, shapes, undo_floats, undo_ints, w) -> None:
    """Put world ``w`` back as ``save_world`` found it (the contact arrays have the
    capacity they had then)."""
    body, body_i, spring, _, contact, contact_i, world_i, time, _ = state
    floats, ints = undo_floats[w], undo_ints[w]
    time[w] = floats[0]
    at = 1
    for i in range(_slots_in_use(shapes)):
        for column in range(TORQUE + 1):
            body[w, i, column] = floats[at + column]
        for column in range(SLEEP_TIME, BODY_F):
            body[w, i, column] = floats[at + column - _COLD]
        at += SAVED_BODY_F
    for k in range(spring.shape[1]):
        spring[w, k, SPRING_ON] = floats[at]
        for column in range(IMPULSE_X, JOINT_TORQUE + 1):
            spring[w, k, column] = floats[at + 1 + column - IMPULSE_X]
        at += SAVED_SPRING_F
    for k in range(WORLD_I):
        world_i[w, k] = ints[k]
    count = world_i[w, CONTACT_COUNT]
    contact[w] = 0.0
    contact_i[w] = 0
    for j in range(count):
        for column in range(CONTACT_F):
            contact[w, j, column] = floats[at + column]
        at += CONTACT_F
    at = WORLD_I
    for i in range(body_i.shape[1]):
        for column in range(BODY_I):
            body_i[w, i, column] = ints[at + column]
        at += BODY_I
    for j in range(count):
        for column in range(CONTACT_I):
            contact_i[w, j, column] = ints[at + column]
        at += CONTACT_I


@kernel
def restore(body, body_i, spring, sensor, contact, contact_i, world_i, time, hull, layout,
            undo_floats, undo_ints, worlds) -> None:  # fmt: skip
    """``restore_world`` for each of ``worlds`` (``layout``: ``Layout.rows``)."""
    state = (body, body_i, spring, sensor, contact, contact_i, world_i, time, hull)
    shapes = layout[: body.shape[1]]
    for w in worlds:
        restore_world(state, shapes, undo_floats, undo_ints, w)


@kernel
def leaves_envelope(body, body_i, shapes, w) -> tuple[int, int]:
    """The first moving body of world ``w`` outside the envelope after a step and what
    is outside (``SPEED``, ``ANGULAR_SPEED``, ``POSITION``, ``NOT_FINITE``), or (-1, -1).

    A body is outside when a coordinate of its centre is beyond ``envelope.COORDINATE``,
    its speed beyond ``envelope.SPEED``, its angular speed beyond
    ``envelope.ANGULAR_SPEED``, or any of these is not a number. The comparisons are
    written so that NaN fails them."""
    for i in range(shapes.shape[0]):
        if shapes[i, 0] == PLANE or body_i[w, i, ENABLED] == 0 or body_i[w, i, AWAKE] == 0:
            continue
        x, y = body[w, i, X], body[w, i, Y]
        vx, vy, omega = body[w, i, VX], body[w, i, VY], body[w, i, OMEGA]
        speed_squared = vx * vx + vy * vy
        if not (abs(x) <= envelope.COORDINATE and abs(y) <= envelope.COORDINATE):
            return i, POSITION if x == x and y == y else NOT_FINITE
        if not (speed_squared <= _SPEED_SQUARED):
            return i, SPEED if speed_squared == speed_squared else NOT_FINITE
        if not (abs(omega) <= envelope.ANGULAR_SPEED):
            return i, ANGULAR_SPEED if omega == omega else NOT_FINITE
    return -1, -1
