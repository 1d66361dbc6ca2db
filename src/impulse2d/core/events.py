"""What a game asks of a step, run inside it: sensors, damage and first contacts.

Rules that a game would otherwise check between steps in Python are engine features
here, so a whole shot runs in compiled code:

* **Sensors** (Box2D v3 has sensor shapes and events): a circle or box region. A moving
  dynamic body whose centre is inside it (or outside, for ``outside=True``) is reported
  in ``state.SENSED`` and, for ``disables=True``, switched off: a pool ball whose centre
  enters a pocket is potted.
* **Damage**: a body's ``HEALTH`` loses the normal impulse of every contact point that
  closed faster than the world's ``damage_speed`` at the start of the step (an impact,
  not the steady push of a resting stack, which closes at no more than about ``g dt``);
  at zero the body is switched off: a block breaks.
* **First contact**: ``state.FIRST_CONTACT`` records the first body a body pushed against
  since the record was cleared: did the cue ball hit a ball?

Switching a body off (here, or by ``body.enabled = False``) wakes what touched it and
drops its cached contacts, so nothing is left resting on a body that is gone.
"""

from __future__ import annotations

import math

from . import context
from ._jit import kernel
from .sleep import wake_neighbours
from .state import (
    AWAKE,
    BODY_A,
    BODY_B,
    CONTACT_COUNT,
    ENABLED,
    FIRST_CONTACT,
    FIXED,
    HEALTH,
    ISLAND,
    PLANE,
    SENSE_DISABLES,
    SENSE_OUTSIDE,
    SENSED,
    SENSOR_ANGLE,
    SENSOR_HH,
    SENSOR_HW,
    SENSOR_ON,
    SENSOR_X,
    SENSOR_Y,
    SLEEP_TIME,
    X,
    Y,
)
from .workspace import APPROACH_SPEED, MOVABLE, STEP_J


@kernel
def forget_contacts(contact, contact_i, world_i, w, slot) -> None:
    """Drop the cached contact points of one body, keeping the others in order."""
    m = 0
    for j in range(world_i[w, CONTACT_COUNT]):
        if contact_i[w, j, BODY_A] == slot or contact_i[w, j, BODY_B] == slot:
            continue
        if m != j:  # column by column: a row copied as a slice needs numba's allocator
            for column in range(contact.shape[2]):
                contact[w, m, column] = contact[w, j, column]
            for column in range(contact_i.shape[2]):
                contact_i[w, m, column] = contact_i[w, j, column]
        m += 1
    contact[w, m : world_i[w, CONTACT_COUNT]] = 0.0  # rows past the count stay zero
    contact_i[w, m : world_i[w, CONTACT_COUNT]] = 0
    world_i[w, CONTACT_COUNT] = m


@kernel
def disable(body, body_i, shapes, contact, contact_i, world_i, w, slot) -> None:
    """Switch a body off in world ``w``: it leaves the step, and what touched it wakes."""
    if body_i[w, slot, ENABLED] == 0:
        return
    wake_neighbours(body, body_i, shapes, contact_i, world_i, w, slot)
    forget_contacts(contact, contact_i, world_i, w, slot)
    body_i[w, slot, ENABLED] = 0
    body_i[w, slot, AWAKE] = 0
    body_i[w, slot, ISLAND] = -1
    body[w, slot, SLEEP_TIME] = 0.0


@kernel
def enable(body, body_i, shapes, contact, contact_i, world_i, w, slot) -> None:
    """Switch a body on in world ``w``, awake (a fixed body is never awake)."""
    if body_i[w, slot, ENABLED] == 1:
        return
    forget_contacts(contact, contact_i, world_i, w, slot)
    body_i[w, slot, ENABLED] = 1
    body_i[w, slot, AWAKE] = 0 if shapes[slot, 1] == FIXED else 1
    body_i[w, slot, ISLAND] = -1
    body[w, slot, SLEEP_TIME] = 0.0


@kernel
def in_region(sensor, sensors, w, q, x, y) -> bool:
    """Whether the point ``(x, y)`` triggers sensor ``q``."""
    dx, dy = x - sensor[w, q, SENSOR_X], y - sensor[w, q, SENSOR_Y]
    hw = sensor[w, q, SENSOR_HW]
    if sensors[q, 0] == 0:  # a circle
        inside = dx * dx + dy * dy < hw * hw
    else:
        c, sn = math.cos(sensor[w, q, SENSOR_ANGLE]), math.sin(sensor[w, q, SENSOR_ANGLE])
        lx, ly = c * dx + sn * dy, -sn * dx + c * dy
        inside = abs(lx) < hw and abs(ly) < sensor[w, q, SENSOR_HH]
    return not inside if sensors[q, 1] & SENSE_OUTSIDE else inside


@kernel
def sense(body, body_i, shapes, sensor, sensors, contact, contact_i, world_i, w, terms, moving,
          count):  # fmt: skip
    """Report, and switch off if the sensor says so, the bodies that moved this step (of
    the ``count`` in ``moving``: ``integrate.list_moving``) and whose centre is in a
    sensor's region (the first sensor, in slot order)."""
    watching = False
    for q in range(sensors.shape[0]):
        watching |= sensors[q, 0] >= 0 and sensor[w, q, SENSOR_ON] == 1.0
    if not watching:
        return
    for k in range(count):
        i = moving[k]
        if terms[i, MOVABLE] == 0.0 or body_i[w, i, ENABLED] == 0:
            continue
        for q in range(sensors.shape[0]):
            if sensors[q, 0] < 0 or sensor[w, q, SENSOR_ON] != 1.0:
                continue
            if in_region(sensor, sensors, w, q, body[w, i, X], body[w, i, Y]):
                body_i[w, i, SENSED] = q
                if sensors[q, 1] & SENSE_DISABLES:
                    disable(body, body_i, shapes, contact, contact_i, world_i, w, i)
                break


@kernel
def record_contacts(body, body_i, w, ctx, points, ids, n) -> bool:
    """First contacts, and the damage of this step's impacts (see the module docstring);
    returns whether anything was damaged."""
    threshold = ctx[context.DAMAGE_SPEED]
    damaged = False
    for k in range(n):
        impulse = points[k, STEP_J]
        if impulse <= 0.0:
            continue
        a, b = ids[k, 0], ids[k, 1]
        if body_i[w, a, FIRST_CONTACT] < 0:
            body_i[w, a, FIRST_CONTACT] = b
        if body_i[w, b, FIRST_CONTACT] < 0:
            body_i[w, b, FIRST_CONTACT] = a
        if points[k, APPROACH_SPEED] < -threshold:
            body[w, a, HEALTH] -= impulse
            body[w, b, HEALTH] -= impulse
            damaged = True
    return damaged


@kernel
def break_bodies(body, body_i, shapes, contact, contact_i, world_i, w) -> None:
    """Switch off the bodies whose health has run out."""
    for i in range(shapes.shape[0]):
        broken = body[w, i, HEALTH] <= 0.0 and body_i[w, i, ENABLED] == 1
        if broken and shapes[i, 0] != PLANE:
            disable(body, body_i, shapes, contact, contact_i, world_i, w, i)
