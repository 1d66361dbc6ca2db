"""Readouts of a world's state: energy, contact impulses, contact points, point queries.

Plain numpy over ``WorldState``: these run between steps, once per call, where
numpy's per-call cost does not matter.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from .core.state import (
    ANCHOR_AX,
    ANCHOR_AY,
    ANCHOR_BX,
    ANCHOR_BY,
    ANGLE,
    APPROACH,
    BODY_A,
    BODY_B,
    BOX,
    CIRCLE,
    CONTACT_COUNT,
    CONTACT_NX,
    CONTACT_NY,
    DYNAMIC,
    ENABLED,
    GROSS_IMPULSE,
    HALF_H,
    HALF_W,
    LINK,
    MASS,
    MOMENT,
    OMEGA,
    PLANE,
    POINT_X,
    POINT_Y,
    POLYGON,
    REST_LENGTH,
    SEPARATION,
    SPRING,
    SPRING_ON,
    STEP_IMPULSE,
    STIFFNESS,
    VX,
    VY,
    Layout,
    WorldState,
    X,
    Y,
)
from .polygons import contains


@dataclass(frozen=True)
class Energy:
    """Energy of a world (J); each field is a float, or one value per world of a batch.

    ``kinetic_linear`` = sum of ``m v^2 / 2``; ``kinetic_rotational`` = sum of
    ``I w^2 / 2``; ``potential`` = sum of ``-m g . position`` (zero at the origin; the
    tutorial writes "mass * gravity", which is a force: the height is missing);
    ``elastic`` = sum over springs of ``k (L - L0)^2 / 2``.
    """

    kinetic_linear: Any
    kinetic_rotational: Any
    potential: Any
    elastic: Any

    @property
    def kinetic(self) -> Any:
        """Linear plus rotational kinetic energy (J)."""
        return self.kinetic_linear + self.kinetic_rotational

    @property
    def total(self) -> Any:
        """Everything: kinetic, potential and elastic (J)."""
        return self.kinetic_linear + self.kinetic_rotational + self.potential + self.elastic


@dataclass(frozen=True)
class ContactPoints:
    """The contact points of one world at its last step, one entry per point: the two
    bodies' slots, the point (m, midway between the surfaces), the unit normal from A to
    B, the separation (m, < 0: overlap), the normal impulse over the step (N s; 0 for a
    speculative point that never touched, or a point resting in a sleeping pile), the
    normal velocity at the step start (m/s, < 0: closing) and the gross impulse, the sizes
    of all its normal and friction pushes over the step summed (N s; at least
    ``impulse``, more where the solver or the bounce took a push back)."""

    slot_a: np.ndarray
    slot_b: np.ndarray
    point: np.ndarray
    normal: np.ndarray
    separation: np.ndarray
    impulse: np.ndarray
    approach: np.ndarray
    gross: np.ndarray

    @property
    def size(self) -> int:
        return int(self.slot_a.size)


def spring_lengths(state: WorldState, layout: Layout) -> np.ndarray:
    """Anchor distance of every spring slot in every world, shape (B, S) (0 for free)."""
    ends = layout.springs
    a, b = np.maximum(ends[:, 0], 0), np.maximum(ends[:, 1], 0)
    body, spring = state.body, state.spring

    def anchor(slot: np.ndarray, lx: int, ly: int) -> tuple[np.ndarray, np.ndarray]:
        angle = body[:, slot, ANGLE]
        c, s = np.cos(angle), np.sin(angle)
        x = body[:, slot, X] + c * spring[:, :, lx] - s * spring[:, :, ly]
        y = body[:, slot, Y] + s * spring[:, :, lx] + c * spring[:, :, ly]
        return x, y

    ax, ay = anchor(a, ANCHOR_AX, ANCHOR_AY)
    bx, by = anchor(b, ANCHOR_BX, ANCHOR_BY)
    return np.where(ends[:, 0] >= 0, np.sqrt((bx - ax) ** 2 + (by - ay) ** 2), 0.0)


def energy(state: WorldState, layout: Layout, gravity: np.ndarray) -> Energy:
    """Kinetic, gravitational and spring energy per world; fixed and kinematic bodies are
    left out (they are driven, not part of the system)."""
    body = state.body
    counted = (layout.motion == DYNAMIC) & (layout.kind >= 0) & (layout.kind != PLANE)
    counted = counted[None, :] & (state.body_i[:, :, ENABLED] == 1)
    mass = np.where(counted, body[:, :, MASS], 0.0)
    moment = np.where(counted, body[:, :, MOMENT], 0.0)
    linear = 0.5 * (mass * (body[:, :, VX] ** 2 + body[:, :, VY] ** 2)).sum(axis=1)
    rotational = 0.5 * (moment * body[:, :, OMEGA] ** 2).sum(axis=1)
    potential = -(mass * (gravity[0] * body[:, :, X] + gravity[1] * body[:, :, Y])).sum(axis=1)
    ends = layout.springs
    on = (ends[:, 0] >= 0)[None, :] & (state.spring[:, :, SPRING_ON] == 1.0)
    on &= state.spring[:, :, LINK] == SPRING  # joints store no energy of their own
    a, b = np.maximum(ends[:, 0], 0), np.maximum(ends[:, 1], 0)
    on &= (state.body_i[:, a, ENABLED] == 1) & (state.body_i[:, b, ENABLED] == 1)
    stretch = spring_lengths(state, layout) - state.spring[:, :, REST_LENGTH]
    elastic = np.where(on, 0.5 * state.spring[:, :, STIFFNESS] * stretch**2, 0.0).sum(axis=1)
    if state.batch_size == 1:
        return Energy(
            float(linear[0]), float(rotational[0]), float(potential[0]), float(elastic[0])
        )
    return Energy(linear, rotational, potential, elastic)


def contact_points(state: WorldState, world: int) -> ContactPoints:
    count = int(state.world_i[world, CONTACT_COUNT])
    rows, ids = state.contact[world, :count], state.contact_i[world, :count]
    return ContactPoints(
        slot_a=ids[:, BODY_A].copy(),
        slot_b=ids[:, BODY_B].copy(),
        point=rows[:, [POINT_X, POINT_Y]].copy(),
        normal=rows[:, [CONTACT_NX, CONTACT_NY]].copy(),
        separation=rows[:, SEPARATION].copy(),
        impulse=rows[:, STEP_IMPULSE].copy(),
        approach=rows[:, APPROACH].copy(),
        gross=rows[:, GROSS_IMPULSE].copy(),
    )


def impulses(state: WorldState, approach_speed: float) -> np.ndarray:
    """Per world and slot, the sum of the normal impulses of the last step's contact
    points it took part in, keeping only points closing faster than ``approach_speed``
    (all points when it is 0). Shape (B, N)."""
    total = np.zeros(state.body.shape[:2])
    for w in range(state.batch_size):
        count = int(state.world_i[w, CONTACT_COUNT])
        rows, ids = state.contact[w, :count], state.contact_i[w, :count]
        impulse = rows[:, STEP_IMPULSE]
        if approach_speed > 0.0:
            impulse = np.where(rows[:, APPROACH] < -approach_speed, impulse, 0.0)
        np.add.at(total[w], ids[:, BODY_A], impulse)
        np.add.at(total[w], ids[:, BODY_B], impulse)
    return total


def touches(state: WorldState) -> tuple[np.ndarray, ...]:
    """``(world, slot_a, slot_b, impulse)`` of the points that pushed in the last step."""
    counts = state.world_i[:, CONTACT_COUNT]
    rows = np.arange(state.contact_capacity)[None, :] < counts[:, None]
    pushed = rows & (state.contact[:, :, STEP_IMPULSE] > 0.0)
    world, row = np.nonzero(pushed)
    ids = state.contact_i[world, row]
    return world, ids[:, BODY_A], ids[:, BODY_B], state.contact[world, row, STEP_IMPULSE]


def containing(state: WorldState, layout: Layout, point: np.ndarray, world: int) -> np.ndarray:
    """The slots of the enabled circles, boxes and polygons of one world that contain
    ``point``."""
    body = state.body[world]
    dx, dy = point[0] - body[:, X], point[1] - body[:, Y]
    c, s = np.cos(body[:, ANGLE]), np.sin(body[:, ANGLE])
    lx, ly = c * dx + s * dy, -s * dx + c * dy
    hw, hh = body[:, HALF_W], body[:, HALF_H]
    kind = layout.kind
    inside = np.where(
        kind == CIRCLE, np.hypot(lx, ly) <= hw, (np.abs(lx) <= hw) & (np.abs(ly) <= hh)
    )
    for slot in np.flatnonzero(kind == POLYGON):
        inside[slot] = contains(state.hull[world, slot], np.array([lx[slot], ly[slot]]))
    solid = (kind == CIRCLE) | (kind == BOX) | (kind == POLYGON)
    inside &= solid & (state.body_i[world, :, ENABLED] == 1)
    return np.flatnonzero(inside)
