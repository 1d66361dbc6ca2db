"""Scripted players for both games, from the observation alone, as yardsticks for learning.

* ``pool_ghost_ball(obs)``: for every object ball and pocket, the "ghost ball" method: the
  cue ball must arrive where it touches the object ball on the line from the pocket
  through that ball, at ``object - 2 r * unit(pocket - object)``. The shot with the
  smallest cut angle whose two paths are clear of other balls is taken, at the speed that
  brings the object ball to the pocket with some to spare.
* ``slingshot_ballistic(obs)``: the launch angle that puts the bird through the nearest
  pig's centre, from the drag-free projectile equation, at full speed.

Both take one observation or a batch (rows) and return actions in [-1, 1] (float32), so
they drive a single env, a vector env or the SB3 adapter alike::

    obs, info = env.reset(seed=0)
    obs, reward, terminated, truncated, info = env.step(pool_ghost_ball(obs))
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from . import pool, slingshot
from ._core import range_to_action

GRAVITY = 9.81


def pool_ghost_ball(observation: Any) -> np.ndarray:
    """Ghost-ball shots for Pool2D observations, shape ``(2,)`` or ``(n, 2)``."""
    return _rows(observation, _pool_row)


def slingshot_ballistic(observation: Any, arc: str = "low") -> np.ndarray:
    """Ballistic launches for Slingshot2D observations, shape ``(2,)`` or ``(n, 2)``.
    ``arc``: the ``"low"`` (direct) or ``"high"`` (lobbed) of the two solutions."""
    if arc not in ("low", "high"):
        raise ValueError(f"arc must be 'low' or 'high', got {arc!r}")
    return _rows(observation, lambda row: _slingshot_row(row, arc == "high"))


def _rows(observation: Any, act: Any) -> np.ndarray:
    obs = np.asarray(observation, np.float64)
    if obs.ndim not in (1, 2):
        raise ValueError(f"observation must be one vector or a batch of rows, got {obs.shape}")
    actions = np.array([act(row) for row in np.atleast_2d(obs)], np.float32)
    return actions[0] if obs.ndim == 1 else actions


# -- pool ------------------------------------------------------------------------------------
def _pool_row(row: np.ndarray) -> np.ndarray:
    positions, flags = pool.ball_positions(row)
    xy, on_table = positions[0], flags[0]
    targets = np.flatnonzero(on_table[1:]) + 1
    shots = pool_shots(row)
    if not shots:  # nothing clear: hit the nearest ball full on, firmly
        if targets.size == 0:
            return np.zeros(2)
        nearest = targets[np.argmin(np.hypot(*(xy[targets] - xy[0]).T))]
        aim, speed = xy[nearest] - xy[0], 3.0
    else:
        _, aim, speed, _ = max(shots, key=lambda shot: shot[0])
    return pool_action(aim, speed)


def pool_action(aim: np.ndarray, speed: float) -> np.ndarray:
    """The Pool2D action that sends the cue ball along ``aim`` at ``speed`` (m/s)."""
    strength = np.clip(range_to_action(speed, pool.SPEED_RANGE), -1, 1)
    return np.array([math.atan2(aim[1], aim[0]) / math.pi, strength])


def pool_shots(row: np.ndarray) -> list[tuple[float, np.ndarray, float, int]]:
    """Every ghost-ball shot of one Pool2D observation whose cut is under 70 degrees and
    whose two paths (cue ball to ghost, object ball to pocket) are clear of other balls,
    as ``(score, aim, speed, ball)``: ``score = cos(cut)^2 / (1 + reach + run)`` (m),
    higher for straighter and shorter shots; ``aim`` the cue ball's direction, ``speed``
    its speed (m/s) to bring the object ball to the pocket with some to spare."""
    positions, flags = pool.ball_positions(row)
    xy, on_table = positions[0], flags[0]
    cue = xy[0]
    r = pool.BALL_RADIUS
    pockets, _ = pool.pockets()
    shots = []
    for i in np.flatnonzero(on_table[1:]) + 1:
        obstacle = on_table.copy()
        obstacle[[0, i]] = False  # the cue ball and the target are not in the way
        others = xy[obstacle]
        for pocket in pockets:
            to_pocket = pocket - xy[i]
            run = float(np.hypot(*to_pocket))
            ghost = xy[i] - 2 * r * to_pocket / run
            aim = ghost - cue
            reach = float(np.hypot(*aim))
            if reach < 1e-9:
                continue
            cut = math.acos(np.clip(np.dot(aim, to_pocket) / (reach * run), -1.0, 1.0))
            if cut > math.radians(70):
                continue
            if not (_clear(cue, ghost, others, 2 * r) and _clear(xy[i], pocket, others, 2 * r)):
                continue
            score = math.cos(cut) ** 2 / (1.0 + reach + run)
            shots.append((score, aim, _pool_speed(reach, run, cut), int(i)))
    return shots


def _pool_speed(reach: float, run: float, cut: float) -> float:
    """Cue-ball speed that gets the object ball to the pocket at 0.5 m/s: the object ball
    leaves at ``(1 + e) / 2 * cos(cut)`` of the cue ball's speed at contact, and both roll
    against a constant deceleration ``a`` (``v^2`` falls by ``2 a d`` over a distance d)."""
    a = pool.ROLLING_RESISTANCE
    leave = math.sqrt(0.5**2 + 2 * a * run)
    contact = leave / ((1 + pool.RESTITUTION_BALL) / 2 * max(math.cos(cut), 0.2))
    return math.sqrt(contact**2 + 2 * a * reach) * 1.2


def _clear(start: np.ndarray, end: np.ndarray, balls: np.ndarray, gap: float) -> bool:
    """No ball centre within ``gap`` of the segment from ``start`` to ``end``."""
    if balls.size == 0:
        return True
    d = end - start
    length2 = float(d @ d)
    t = np.clip(((balls - start) @ d) / max(length2, 1e-12), 0.0, 1.0)
    closest = start + t[:, None] * d
    return bool(np.all(np.hypot(*(balls - closest).T) > gap))


# -- slingshot -------------------------------------------------------------------------------
def ballistic_angle(dx: Any, dy: Any, speed: Any, high: Any) -> np.ndarray:
    """Launch angles (rad) that put a drag-free projectile leaving at ``speed`` (m/s)
    through the point ``(dx, dy)`` (m) from the launch point: the lower root of

        y = x tan(t) - g x^2 / (2 v^2 cos^2 t),  a quadratic in tan(t),

    or the upper one where ``high``. Out of reach (or behind), 45 degrees: the farthest
    throw. Arrays broadcast; the result is float64."""
    dx, dy, v = (np.asarray(a, np.float64) for a in (dx, dy, speed))
    disc = v**4 - GRAVITY * (GRAVITY * dx * dx + 2 * dy * v**2)
    reach = (disc >= 0) & (dx > 0)
    root = np.sqrt(np.where(reach, disc, 0.0))
    tangent = (v**2 + np.where(high, root, -root)) / (GRAVITY * np.where(reach, dx, 1.0))
    return np.where(reach, np.arctan(tangent), math.pi / 4)


def _slingshot_row(row: np.ndarray, high: bool) -> np.ndarray:
    slots = row[:-1].reshape(-1, slingshot.FEATURES)[: slingshot.MAX_PIGS]
    alive = np.flatnonzero(slots[:, 0] > 0.5)
    if alive.size == 0:
        return np.zeros(2)
    x, y = slingshot.slot_positions(slots[alive])
    k = int(np.argmin(x))
    dx, dy = x[k] - slingshot.SLING[0], y[k] - slingshot.SLING[1]
    angle = float(ballistic_angle(dx, dy, slingshot.SPEED_RANGE[1], high))
    lo, hi = slingshot.ANGLE_RANGE
    angle = min(max(angle, lo), hi)
    return np.array([range_to_action(angle, slingshot.ANGLE_RANGE), 1.0])
