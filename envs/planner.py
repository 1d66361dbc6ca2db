"""Planners for Pool2D and Slingshot2D: every shot chosen by playing its candidates first.

The engine steps a batch of tables as one, and a game's position saves and restores in
microseconds; a planner is what that is for. For each shot ``PoolPlanner`` (and
``SlingshotPlanner``, with its own candidates) does this:

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
physics, to rest). ``SlingshotPlanner`` lists, for every pig standing, the launches on
the drag-free parabola through it at several speeds, low and high arc, a little off
either way, and scores by the game's reward alone. A planner sees the game, not only the
observation: construct it with the env (``gym.make("Pool2D-v0", ...)``) and call it with
the observation, as the scripted players are called::

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

from . import pool, slingshot
from ._core import GameState, ShotGame, range_to_action
from .baselines import ballistic_angle, pool_action, pool_shots


class ShotPlanner:
    """Chooses each shot of a single shot-game env by playing candidates from its position
    in one batch (see the module docstring); a game's planner lists the candidates
    (``candidate_actions``), builds the batch (``_table``) and may score the position
    left (``_ease``)."""

    game_class: type = ShotGame

    def __init__(self, env: Any, candidates: int, position_weight: float, seed: int) -> None:
        game = getattr(env.unwrapped, "game", None)
        if not isinstance(game, self.game_class) or game.batch_size != 1:
            name = self.game_class.__name__[: -len("Game")]
            raise ValueError(f"env must be a single {name}2D env, got {env.unwrapped!r}")
        self.game = game
        self.candidates = _checks.int_in("candidates", candidates, 1, 65536)
        self.position_weight = _checks.number_in("position_weight", position_weight, 0.0, 1e3, "")
        self.rng = np.random.default_rng(_checks.int_in("seed", seed, 0, 2**63 - 1, "2**63 - 1"))
        self.table = self._table(game, self.candidates)

    def __call__(self, observation: Any) -> np.ndarray:
        """The action to play from the env's position (``observation`` is its own)."""
        row = np.asarray(observation, np.float64).reshape(-1)
        actions = self.candidate_actions(row)
        scores = self.play(actions)
        return actions[int(np.argmax(scores))]

    def candidate_actions(self, row: np.ndarray) -> np.ndarray:
        raise NotImplementedError

    def _table(self, game: Any, count: int) -> Any:
        raise NotImplementedError

    def _ease(self, rows: np.ndarray) -> np.ndarray:
        """How good the position each row leaves is, for the next shot (0: no credit)."""
        return np.zeros(len(rows))

    def _filled(self, listed: list[np.ndarray]) -> np.ndarray:
        """``listed`` actions cut or filled with seeded random actions to the budget, as
        float32: the env's action space hands them on so, a break is chaotic, and a shot
        played from the float64 a float32 rounds from is another shot."""
        spare = self.candidates - len(listed)
        filler = self.rng.uniform(-1.0, 1.0, (max(spare, 0), 2))
        actions = np.concatenate([np.array(listed).reshape(-1, 2), filler])[: self.candidates]
        return np.clip(actions, -1.0, 1.0).astype(np.float32)

    def play(self, actions: np.ndarray) -> np.ndarray:
        """Each candidate's score: the reward of playing it from the env's position plus
        ``position_weight`` times the ease of the position it leaves."""
        table, saved = self.table, self.game.save_state()
        count = self.candidates
        table.restore_state(
            GameState(
                saved.world,  # one world's snapshot: restored into every table
                saved.rngs * count,
                {name: np.repeat(rows, count, axis=0) for name, rows in saved.rows.items()},
            )
        )
        rewards, terminated, _ = table.shoot(np.arange(count), actions)
        if self.position_weight == 0.0:
            return rewards
        return rewards + self.position_weight * np.where(
            terminated, 0.0, self._ease(table.observe())
        )


class PoolPlanner(ShotPlanner):
    """Pool2D: the best ``pairs`` ghost-ball shots (ball and pocket), each at ``speeds``
    times its speed and turned by ``turns`` (rad); the position scored by the next
    shot's best ghost-ball score."""

    game_class = pool.PoolGame

    def __init__(
        self,
        env: Any,
        candidates: int = 128,
        speeds: tuple[float, ...] = (0.8, 1.0, 1.4, 2.0),
        turns: tuple[float, ...] = (-0.004, 0.0, 0.004),
        position_weight: float = 0.5,
        seed: int = 0,
    ) -> None:
        self.speeds = tuple(_checks.positive("speeds", s) for s in _sequence("speeds", speeds))
        self.turns = _sequence("turns", turns)
        super().__init__(env, candidates, position_weight, seed)
        self.pairs = max(1, self.candidates // (len(self.speeds) * len(self.turns)))

    def _table(self, game: Any, count: int) -> Any:
        return pool.PoolGame(
            count, num_balls=game.num_balls, layout=game.layout,
            max_shot_seconds=game.max_shot_steps * game.dt, shaping=game.shaping,
        )  # fmt: skip

    def candidate_actions(self, row: np.ndarray) -> np.ndarray:
        """``(candidates, 2)`` float32 actions: the best ghost-ball shots, at each speed
        factor and turn, then seeded random actions to fill the budget."""
        shots = sorted(pool_shots(row), key=lambda shot: -shot[0])[: self.pairs]
        return self._filled(
            [
                pool_action(_turned(aim, turn), speed * factor)
                for _, aim, speed, _ in shots
                for factor in self.speeds
                for turn in self.turns
            ]
        )

    def _ease(self, rows: np.ndarray) -> np.ndarray:
        return np.array([max((shot[0] for shot in pool_shots(r)), default=0.0) for r in rows])


class SlingshotPlanner(ShotPlanner):
    """Slingshot2D: for every pig still standing, the launch on the drag-free parabola
    through its centre (``baselines.ballistic_angle``) at each of ``speeds`` launch
    speeds (m/s; unreachable ones dropped), low and high arc, and ``turns`` (rad) off
    it; scored by the game's reward alone (pigs and blocks destroyed, the bird bonus)."""

    game_class = slingshot.SlingshotGame

    def __init__(
        self,
        env: Any,
        candidates: int = 128,
        speeds: tuple[float, ...] = (10.0, 12.0, 14.0, 16.0, 18.0, 20.0),
        turns: tuple[float, ...] = (-0.03, 0.0, 0.03),
        seed: int = 0,
    ) -> None:
        self.speeds = tuple(
            _checks.number_in("speeds", v, *slingshot.SPEED_RANGE, " m/s")
            for v in _sequence("speeds", speeds)
        )
        self.turns = _sequence("turns", turns)
        super().__init__(env, candidates, 0.0, seed)

    def _table(self, game: Any, count: int) -> Any:
        return slingshot.SlingshotGame(
            count, level=game.level, num_birds=game.num_birds,
            max_shot_seconds=game.max_shot_steps * game.dt, num_levels=game.num_levels,
            start_level=game.start_level, templates=game.templates or None,
        )  # fmt: skip

    def candidate_actions(self, row: np.ndarray) -> np.ndarray:
        slots = row[:-1].reshape(-1, slingshot.FEATURES)[: slingshot.MAX_PIGS]
        alive = np.flatnonzero(slots[:, 0] > 0.5)
        x, y = slingshot.slot_positions(slots[alive])
        dx, dy = x - slingshot.SLING[0], y - slingshot.SLING[1]
        listed = []
        for speed in self.speeds:
            strength = range_to_action(speed, slingshot.SPEED_RANGE)
            for high in (False, True):
                angles = ballistic_angle(dx, dy, speed, high)
                for angle in np.atleast_1d(angles):
                    for turn in self.turns:
                        aim = range_to_action(angle + turn, slingshot.ANGLE_RANGE)
                        listed.append(np.array([aim, strength]))
        return self._filled(listed)


def _sequence(name: str, values: Any) -> tuple[float, ...]:
    """A non-empty sequence of finite numbers, as floats."""
    array = _checks.real_array(name, values)
    if array.ndim != 1 or array.size == 0:
        raise ValueError(f"{name} must be a non-empty sequence of numbers, got {values!r}")
    return tuple(float(v) for v in array)


def _turned(aim: np.ndarray, turn: float) -> np.ndarray:
    c, s = math.cos(turn), math.sin(turn)
    return np.array([c * aim[0] - s * aim[1], s * aim[0] + c * aim[1]])
