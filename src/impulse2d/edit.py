"""Edits of a world's state from outside the step: what the facades' setters do.

Each edit writes the arrays, keeps the columns derived from what it wrote consistent
(inverse mass, moment, bounding radius), and wakes what it touches, only in the worlds
whose value changed: a game that rewrites one world of a batch (a respotted cue ball)
must leave the others exactly as they were, or a batch would stop stepping like the
worlds alone. Waking runs the same compiled code the step uses (``core.edits``).

Each takes the state and the layout it edits, as ``readouts`` takes what it reads, not
the ``World``: a facade passes its world's two, and nothing here reaches into the rest
of a world.
"""

from __future__ import annotations

import numpy as np

from . import _checks, envelope
from .core import edits
from .core.state import (
    ANGLE,
    ANGULAR_DRAG,
    AWAKE,
    BOUND,
    BOUND_RADIUS,
    BOX,
    CIRCLE,
    COS,
    DAMP_H,
    DYNAMIC,
    ENABLED,
    FIXED,
    FX,
    HALF_H,
    HALF_W,
    INV_MASS,
    INV_MOMENT,
    ISLAND,
    KINEMATIC,
    LINEAR_DRAG,
    MASS,
    MOMENT,
    OMEGA,
    POLYGON,
    SIN,
    SLEEP_TIME,
    TORQUE,
    UNIT_MOMENT,
    VX,
    VY,
    Layout,
    WorldState,
    X,
    Y,
)

VELOCITY_COLUMNS = (VX, VY, OMEGA)


def wake(
    state: WorldState, layout: Layout, worlds: np.ndarray, slot: int, neighbours: bool = False
) -> None:
    """Wake a body's island in ``worlds`` (and, with ``neighbours``, what touched it)."""
    if worlds.size:
        s = state
        edits.wake_bodies(
            s.body,
            s.body_i,
            layout.rows,
            s.contact_i,
            s.world_i,
            worlds.astype(np.int64),
            slot,
            neighbours,
        )


def forget(state: WorldState, slot: int) -> None:
    """Drop the cached contacts of a slot in every world (it is new, or leaving)."""
    s = state
    edits.forget_body_contacts(s.contact, s.contact_i, s.world_i, slot)


def write_body(
    state: WorldState,
    layout: Layout,
    slot: int,
    columns: list[int],
    values: np.ndarray,
    moves: bool,
) -> None:
    """Write ``values`` (B, k) into a body's ``columns`` and wake it where they changed
    (``moves``: it was teleported or resized, so what rested on it wakes too)."""
    body, motion = state.body, int(layout.motion[slot])
    velocity_only = set(columns) <= set(VELOCITY_COLUMNS)
    if motion == FIXED and velocity_only and np.any(values != 0.0):
        name = "angular_velocity" if columns == [OMEGA] else "velocity"
        raise ValueError(f"{name} of a fixed body must be 0; use kinematic=True")
    # A column or a 2-vector is a run of adjacent columns (``Column`` makes sure): a
    # slice is a view, written through, where a list would copy out and scatter back.
    rows = body[:, slot, columns[0] : columns[-1] + 1]
    changed = _changed_worlds(rows, values)
    rows[...] = values
    refresh_derived(state, slot, columns)
    if changed.size == 0:
        return
    if motion == KINEMATIC and velocity_only:
        # A kinematic body is awake while it moves.
        moving = (body[changed, slot, VX : OMEGA + 1] != 0.0).any(axis=1)
        state.body_i[changed, slot, AWAKE] = moving & (state.body_i[changed, slot, ENABLED] == 1)
    wake(state, layout, changed, slot, neighbours=moves)


def _changed_worlds(rows: np.ndarray, values: np.ndarray) -> np.ndarray:
    """The worlds (indices) where ``values`` (B, k) differ from ``rows`` (B, k); a small
    batch compared in plain Python (numpy's reductions cost more than the comparison)."""
    if values.size <= _checks.FEW_ENTRIES:
        old, new = rows.tolist(), values.tolist()
        return np.array([w for w in range(len(old)) if old[w] != new[w]], np.int64)
    return np.flatnonzero((rows != values).any(axis=1))


def write_rows(
    state: WorldState, table: str, slot: int, columns: list[int], values: np.ndarray
) -> None:
    """Write ``values`` (B, k) into ``columns`` of a slot's row of ``state.<table>`` (a
    spring's or a sensor's: nothing derived follows, and they wake nothing themselves)."""
    getattr(state, table)[:, slot, columns] = values


def refresh_derived(state: WorldState, slot: int, columns: list[int]) -> None:
    """Keep the derived columns of a body current after a write: the rotation's cosine
    and sine, and (invalidated, recomputed at the next step) the drag factors."""
    body = state.body[:, slot]
    if ANGLE in columns:
        body[:, COS], body[:, SIN] = np.cos(body[:, ANGLE]), np.sin(body[:, ANGLE])
    if LINEAR_DRAG in columns or ANGULAR_DRAG in columns:
        body[:, DAMP_H] = 0.0


def rebuild_mass(state: WorldState, layout: Layout, slot: int) -> None:
    """Moment of inertia, inverse mass and moment, and bounding radius of a body, from its
    mass and size, in every world: a disc ``m r^2 / 2``, a box ``m (w^2 + h^2) / 12``, a
    polygon its mass times its outline's moment per kg."""
    body = state.body[:, slot]
    kind, motion = int(layout.kind[slot]), int(layout.motion[slot])
    if kind == CIRCLE:
        body[:, HALF_H] = body[:, HALF_W]
    mass, hw, hh = body[:, MASS], body[:, HALF_W], body[:, HALF_H]
    if kind == CIRCLE:
        moment, bound = 0.5 * mass * hw * hw, hw
    elif kind == BOX:
        # (w^2 + h^2) / 12 with w = 2 hw: (4 hw^2 + 4 hh^2) / 12 = (hw^2 + hh^2) / 3
        moment, bound = mass * (hw * hw + hh * hh) / 3.0, np.sqrt(hw * hw + hh * hh)
    elif kind == POLYGON:  # its outline holds the moment per kg and the bounding radius
        outline = state.hull[:, slot]
        moment, bound = mass * outline[:, UNIT_MOMENT], outline[:, BOUND_RADIUS].copy()
    else:
        moment, bound = np.zeros_like(mass), np.zeros_like(mass)
    dynamic = motion == DYNAMIC and kind in (CIRCLE, BOX, POLYGON)
    body[:, MOMENT], body[:, BOUND] = moment, bound
    body[:, INV_MASS] = 1.0 / mass if dynamic else 0.0
    body[:, INV_MOMENT] = 1.0 / moment if dynamic else 0.0


def set_enabled(state: WorldState, layout: Layout, slot: int, flags: np.ndarray) -> None:
    """Switch a body on or off per world (``flags`` (B,) bool), only where it changes."""
    s = state
    changed = np.flatnonzero((s.body_i[:, slot, ENABLED] == 1) != flags)
    if changed.size:
        edits.switch_bodies(
            s.body,
            s.body_i,
            layout.rows,
            s.contact,
            s.contact_i,
            s.world_i,
            changed.astype(np.int64),
            flags[changed],
            slot,
        )


def apply(
    state: WorldState,
    layout: Layout,
    slot: int,
    force: bool,
    push: np.ndarray,
    point: np.ndarray | None,
) -> None:
    """A force over the next step, or an impulse now (``push`` (B, 2)), at ``point`` (B, 2)
    (default: the centre), with the torque ``r x push``; wakes the body where it is pushed
    (a batch of shots where some worlds sit out must leave those as they are).

    What the push leads to is checked against the envelope before anything is written:
    the speeds an impulse leaves, the acceleration ``F / m`` of the body's total force."""
    body = state.body[:, slot]
    centre = body[:, X : Y + 1]
    r = np.zeros_like(push) if point is None else point - centre
    torque = r[:, 0] * push[:, 1] - r[:, 1] * push[:, 0]
    if force:
        total = body[:, FX : TORQUE + 1] + np.column_stack([push, torque])
        acceleration = total[:, :2] * body[:, INV_MASS, None]
        _checks.magnitude_at_most(
            "force (over mass)", acceleration, envelope.ACCELERATION, " m/s^2"
        )
        body[:, FX : TORQUE + 1] = total
    else:
        velocity = body[:, VX : OMEGA + 1] + np.column_stack(
            [push * body[:, INV_MASS, None], torque * body[:, INV_MOMENT]]
        )
        speed = envelope.SPEED
        _checks.magnitude_at_most(
            "impulse (the velocity it leaves)", velocity[:, :2], speed, " m/s"
        )
        spin = envelope.ANGULAR_SPEED
        _checks.within("impulse (the spin it leaves)", velocity[:, 2], -spin, spin, " rad/s")
        body[:, VX : OMEGA + 1] = velocity
    wake(state, layout, np.flatnonzero(np.any(push != 0.0, axis=1)), slot)


def stop(state: WorldState, layout: Layout, worlds: np.ndarray) -> None:
    """Everything in ``worlds`` at rest at once: velocities zero, every body asleep, each
    dynamic body its own island (so any touch wakes it alone)."""
    s = state
    movers = np.flatnonzero(layout.motion != FIXED)
    dynamic = np.flatnonzero((layout.motion == DYNAMIC) & (layout.kind >= 0))
    rows = worlds[:, None]
    s.body[rows, movers, VX : OMEGA + 1] = 0.0
    s.body_i[rows, movers, AWAKE] = 0
    s.body[rows, dynamic, SLEEP_TIME] = 0.0
    s.body_i[rows, dynamic, ISLAND] = dynamic[None, :]
