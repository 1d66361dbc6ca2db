"""The best shots on the table: the call-shot action for full racks
(``Pool2DRackBestShots-v0``).

``PoolCallShot`` (``callshot.py``) offers the six pockets of one ball, the one nearest the
cue ball. On a full rack that ball is often the wrong one: its pockets are blocked or
cut thin while another ball sits over a pocket, and a player who must shoot it fouls
(the rack agent of ``Pool2DRackCallShot-v0`` scratches on a tenth of its shots; the
ghost-ball player, free to choose, on 3 %). Here the agent chooses among the ``SHOTS``
best shots on the whole table, every object ball into every pocket ranked as the
ghost-ball player ranks them:

    score = cos(cut)^2 / (1 + reach + run)

over the shots whose cut is under 70 degrees and whose two paths (cue ball to the ghost
point, object ball to the pocket) are clear of every other ball (clearance above one
ball diameter); then, if fewer than ``SHOTS`` are, the blocked or thin ones by the same
score. The action is the call-shot one, eight numbers: six preferences, one per offered
shot (best first), a trim and a speed within the called shot's window
(``callshot.called_shot``). Each offered shot is described by ``PER_SHOT`` numbers:
whether it is clear (``valid``), its score, the ball's offset from the cue ball (m), and
the call-shot features of that ball and pocket (cut, run, reach, clearances, the speed
window). Rank 1 at ``s`` near the bottom of its window is close to the ghost-ball
player; what there is to learn is when another shot, or another speed, leaves the
table better.
"""

from __future__ import annotations

import math
from typing import Any

import gymnasium as gym
import numpy as np

from . import pool
from .callshot import (
    CLEARANCE_CAP,
    POCKETS,
    REACH_CAP,
    _CallShot,
    _CallShotVector,
    _clearance,
    _Task,
    called_shot,
    pool_shots,
    speed_window,
)

SHOTS = 6  # shots offered (the action's six preferences)
PER_SHOT = ("valid", "score", "dx", "dy", "sin", "cos", "run", "reach", "clear_cue",
            "clear_ball", "pot_speed", "scratch_speed")  # fmt: skip
FEATURES = SHOTS * len(PER_SHOT)
MAX_CUT = math.radians(70.0)


def table_shots(observation: Any) -> dict[str, np.ndarray]:
    """Every object ball into every pocket, for Pool2D observations ``(n, 3 (k + 1))``:
    ``pool_shots``'s numbers, ``ball`` (its index, 1..k), ``pocket`` (0..5), the
    clearances of both paths (each ball its own target: it is not in its own way),
    ``valid`` and ``score``, each ``(n, 6 k)``, ball by ball, pocket by pocket."""
    xy, on_table = pool.ball_positions(observation)
    n, k = xy.shape[0], xy.shape[1] - 1
    cue, balls = xy[:, 0], xy[:, 1:]
    shots = pool_shots(np.repeat(cue, k, axis=0), balls.reshape(-1, 2))
    out = {key: v.reshape(n, k * len(POCKETS), *v.shape[2:]) for key, v in shots.items()}
    ball = np.repeat(np.arange(1, k + 1), len(POCKETS))  # (6 k,)
    pocket = np.tile(np.arange(len(POCKETS)), k)
    # Each segment's obstacles: the object balls on the table but its own target.
    obstacle = np.broadcast_to(on_table[:, None, :], (n, ball.size, k + 1)).copy()
    obstacle[:, :, 0] = False
    obstacle[:, np.arange(ball.size), ball] = False
    target_xy = xy[:, ball]  # (n, 6 k, 2)
    out["clear_cue"] = _clearance(np.broadcast_to(cue[:, None], target_xy.shape), out["ghost"],
                                  xy, obstacle)  # fmt: skip
    out["clear_ball"] = _clearance(target_xy, np.broadcast_to(POCKETS[pocket], target_xy.shape),
                                   xy, obstacle)  # fmt: skip
    present = on_table[:, ball]
    out["valid"] = (present & (out["reach"] > 1e-9) & (out["cos"] > math.cos(MAX_CUT))
                    & (out["clear_cue"] > 1.0) & (out["clear_ball"] > 1.0))  # fmt: skip
    out["score"] = np.where(present, np.maximum(out["cos"], 0.0) ** 2
                            / (1.0 + out["reach"] + out["run"]), 0.0)  # fmt: skip
    out["ball"] = np.broadcast_to(ball, (n, ball.size))
    out["pocket"] = np.broadcast_to(pocket, (n, ball.size))
    out["present"] = present
    return out


def best_shots(observation: Any) -> dict[str, np.ndarray]:
    """The ``SHOTS`` best shots of each table (module docstring), best first: the
    entries of ``table_shots`` ``(n, SHOTS)``, the target ``ball`` and ``pocket``
    positions ``(n, SHOTS, 2)`` (m) as ``ball_xy`` and ``pocket_xy``, the speed window
    ``pot_speed`` and ``scratch_speed``, the ``cue`` ``(n, 2)`` and ``has_target``."""
    xy, on_table = pool.ball_positions(observation)
    every = table_shots(observation)
    # Clear shots first, then blocked ones, then balls already potted; by score within.
    key = every["score"] + 2.0 * every["valid"] + 2.0 * every["present"]
    order = np.argsort(-key, axis=1, kind="stable")[:, :SHOTS]
    shot = {name: np.take_along_axis(value, order, axis=1)
            for name, value in every.items() if value.ndim == 2}  # fmt: skip
    shot["ghost"] = np.take_along_axis(every["ghost"], order[..., None], axis=1)
    rows = np.arange(len(order))[:, None]
    shot["ball_xy"] = xy[rows, shot["ball"]]
    shot["pocket_xy"] = POCKETS[shot["pocket"]]
    shot["cue"] = xy[:, 0]
    shot["has_target"] = on_table[:, 1:].any(axis=1)
    window = {key: shot[key] for key in ("ghost", "cue", "cos", "run", "reach")}
    window.update(ball=shot["ball_xy"], pocket=shot["pocket_xy"])
    shot["pot_speed"], shot["scratch_speed"] = speed_window(window)
    return shot


def best_shot_features(observation: Any) -> np.ndarray:
    """``(n, FEATURES)`` float32: ``PER_SHOT`` numbers for each offered shot, best first;
    all 0 for a table with no object ball left."""
    shot = best_shots(observation)
    offset = shot["ball_xy"] - shot["cue"][:, None, :]
    shot = {**shot, "dx": offset[..., 0], "dy": offset[..., 1]}
    per_shot = np.stack([shot[key].astype(np.float64) for key in PER_SHOT], axis=-1)
    features = per_shot.reshape(len(offset), -1) * shot["has_target"][:, None]
    return features.astype(np.float32)


def best_shot_feature_bounds() -> tuple[np.ndarray, np.ndarray]:
    low = {"valid": 0, "score": 0, "dx": -REACH_CAP, "dy": -REACH_CAP, "sin": -1, "cos": -1,
           "run": 0, "reach": 0, "clear_cue": 0, "clear_ball": 0, "pot_speed": -1,
           "scratch_speed": -1}  # fmt: skip
    high = {"valid": 1, "score": 1, "dx": REACH_CAP, "dy": REACH_CAP, "sin": 1, "cos": 1,
            "run": REACH_CAP, "reach": REACH_CAP, "clear_cue": CLEARANCE_CAP,
            "clear_ball": CLEARANCE_CAP, "pot_speed": 1, "scratch_speed": 1}  # fmt: skip
    return (np.array([low[k] for k in PER_SHOT] * SHOTS, np.float32),
            np.array([high[k] for k in PER_SHOT] * SHOTS, np.float32))  # fmt: skip


def best_shot_actions(actions: Any, observation: Any) -> np.ndarray:
    """``(n, 8)`` actions (six preferences over the offered shots, trim, speed; in [-1,
    1]) and the Pool2D observations they answer -> ``(n, 2)`` game actions (float64)."""
    a = np.asarray(actions, np.float64)
    shot = best_shots(observation)
    called = np.argmax(a[:, :SHOTS], axis=1)
    ball = shot["ball_xy"][np.arange(len(a)), called]
    return called_shot(a[:, SHOTS:], shot, ball, called)


BEST_SHOTS_TASK = _Task(
    "PoolBestShots", pool.PoolGame, SHOTS + 2, best_shot_actions, best_shot_features,
    best_shot_feature_bounds,
)  # fmt: skip


class PoolBestShots(_CallShot):
    """Pool2D with the call-shot action over the table's best shots (module docstring)."""

    task = BEST_SHOTS_TASK


class PoolBestShotsVector(_CallShotVector):
    """The batched Pool2D vector env with the call-shot action over the best shots."""

    task = BEST_SHOTS_TASK


def make(**kwargs: Any) -> gym.Env:
    return PoolBestShots(pool.Pool2DEnv(**kwargs))


def make_vector(**kwargs: Any) -> gym.vector.VectorEnv:
    return PoolBestShotsVector(pool.Pool2DVectorEnv(**kwargs))
