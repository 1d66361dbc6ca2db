"""A planner for Pool2D: every shot chosen by playing its candidates first, in one batch.

The engine steps a batch of tables as one, and a game's position saves and restores in
microseconds; a planner is what that is for. For each shot ``PoolPlanner``:

1. lists candidate actions from the position: the ghost-ball shots of the scripted
   player (``baselines.pool_shots``: every object ball into every pocket with a clear
   path and a cut under 70 degrees), the best ``pairs`` of them, each at ``speeds``
   times its speed and turned by ``turns`` (radians) either way; where no shot is clear,
   seeded random actions;
2. copies the position into every table of its own ``PoolGame`` of ``candidates``
   tables (``save_state``, the world's snapshot restored into all of them) and plays
   every candidate from it in one batched shot (one compiled call);
3. scores each by the game's own reward for the shot plus ``position_weight`` times how
   good the next shot is from where the balls stopped (the best ghost-ball score of the
   new position, ``cos(cut)^2 / (1 + reach + run)``; 0 with no clear shot): position
   play, the cue ball left where the next ball is easy;
4. plays the best (the first of equals).

The budget is ``candidates`` simulated shots of depth one a shot (the game's own
physics, to rest). It sees the game, not only the observation: construct it with the
env (``gym.make("Pool2D-v0", ...)``) and call it with the observation, as the scripted
players are called::

    env = gym.make("Pool2D-v0")
    planner = PoolPlanner(env)
    obs, info = env.reset(seed=0)
    obs, reward, terminated, truncated, info = env.step(planner(obs))
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from impulse2d import _checks

from . import pool
from ._core import GameState
from .baselines import pool_action, pool_shots


class PoolPlanner:
    """Chooses each shot of a single Pool2D env by playing candidates (see the module
    docstring)."""

    def __init__(
        self,
        env: Any,
        candidates: int = 128,
        speeds: tuple[float, ...] = (0.8, 1.0, 1.4, 2.0),
        turns: tuple[float, ...] = (-0.004, 0.0, 0.004),
        position_weight: float = 0.5,
        seed: int = 0,
    ) -> None:
        game = getattr(env.unwrapped, "game", None)
        if not isinstance(game, pool.PoolGame) or game.batch_size != 1:
            raise ValueError(f"env must be a single Pool2D env, got {env.unwrapped!r}")
        self.game = game
        self.candidates = _checks.int_in("candidates", candidates, 1, 65536)
        self.speeds = tuple(_checks.positive("speeds", s) for s in speeds)
        self.turns = tuple(_checks.finite_scalar("turns", t) for t in turns)
        self.position_weight = _checks.number_in("position_weight", position_weight, 0.0, 1e3, "")
        self.pairs = max(1, self.candidates // (len(self.speeds) * len(self.turns)))
        self.rng = np.random.default_rng(seed)
        seconds = game.max_shot_steps * game.dt
        self.table = pool.PoolGame(
            self.candidates, num_balls=game.num_balls, layout=game.layout,
            max_shot_seconds=seconds, shaping=game.shaping,
        )  # fmt: skip

    def __call__(self, observation: Any) -> np.ndarray:
        """The action to play from the env's position (``observation`` is its own)."""
        row = np.asarray(observation, np.float64).reshape(-1)
        actions = self.candidate_actions(row)
        scores = self.play(actions)
        return actions[int(np.argmax(scores))]

    def candidate_actions(self, row: np.ndarray) -> np.ndarray:
        """``(candidates, 2)`` float32 actions: the best ghost-ball shots, at each speed
        factor and turn, then seeded random actions to fill the budget."""
        shots = sorted(pool_shots(row), key=lambda shot: -shot[0])[: self.pairs]
        actions = [
            pool_action(_turned(aim, turn), speed * factor)
            for _, aim, speed, _ in shots
            for factor in self.speeds
            for turn in self.turns
        ]
        spare = self.candidates - len(actions)
        filler = self.rng.uniform(-1.0, 1.0, (max(spare, 0), 2))
        listed = np.concatenate([np.array(actions).reshape(-1, 2), filler])[: self.candidates]
        # float32, as the env's action space hands them on: a break is chaotic, and a
        # shot played from the float64 a float32 rounds from is another shot.
        return np.clip(listed, -1.0, 1.0).astype(np.float32)

    def play(self, actions: np.ndarray) -> np.ndarray:
        """Each candidate's score: the reward of playing it from the env's position plus
        ``position_weight`` times the best ghost-ball score of where the balls stopped."""
        table, saved = self.table, self.game.save_state()
        count = self.candidates
        table.restore_state(
            GameState(
                saved.world,  # one table's snapshot: restored into every table
                saved.rngs * count,
                {name: np.repeat(rows, count, axis=0) for name, rows in saved.rows.items()},
            )
        )
        everywhere = np.arange(count)
        rewards, terminated, _ = table.shoot(everywhere, actions)
        if self.position_weight == 0.0:
            return rewards
        after = table.observe()
        ease = np.array([max((shot[0] for shot in pool_shots(r)), default=0.0) for r in after])
        return rewards + self.position_weight * np.where(terminated, 0.0, ease)


def _turned(aim: np.ndarray, turn: float) -> np.ndarray:
    c, s = math.cos(turn), math.sin(turn)
    return np.array([c * aim[0] - s * aim[1], s * aim[0] + c * aim[1]])
