"""Call-shot tasks: actions that name the shot, and observations that describe it.

A player of pool calls the pocket; a player of Angry Birds picks the pig. The games'
own actions are a direction and a speed, which an agent must compute to a millimetre;
these wrappers give it the action a player thinks in, and the features to choose by.
The game, its rules, its rewards and its episodes are unchanged: a wrapped env plays
the same seeded episodes as the bare one, and scores the same.

``PoolCallShot`` (Pool2D). The action is eight numbers in [-1, 1]: six pocket
preferences, a trim ``c`` and a speed ``s``. The target is the object ball on the table
nearest the cue ball; the pocket the one with the highest preference (a parameterized
action: Hausknecht and Stone, 2016). The cue ball is sent at the target so that its path
passes the target's centre at the signed distance ``2 r clip(sin(cut_p) + 0.25 c, -1,
1)``, ``sin(cut_p)`` being the ghost-ball cut into the called pocket (see ``pool_shots``):
``c = 0`` plays the ghost-ball line, and ``c`` trims it by up to 14 mm at the contact
point (throw, the jaws). ``s`` is how hard, against the called shot's *speed window*
(``speed_window``): ``s = -1`` is the least speed that pots the target on the simplest
model of the table, ``s = 0`` the most at which the cue ball does not follow into a
pocket, ``s = 1`` full speed (``window_speed``): hard enough to get there, soft enough not
to scratch, is ``s`` in [-1, 0] on every table. With the cue ball at ``c0``, the target at
distance ``d`` in direction ``theta``, the game's angle is

    phi = theta + asin(2 r sine / d),

since a line at ``phi`` from the cue ball passes the target's centre at ``d sin(phi -
theta)``. The observation is the game's, followed by ``POOL_FEATURES`` numbers about
the shots at the target (``pool_features``).

``SlingshotCallShot`` (Slingshot2D). The action is seven numbers in [-1, 1]: four pig
preferences, an arc ``h``, a trim ``t`` and a speed ``s``. The bird is launched at the
game's speed for ``s`` along the drag-free parabola through the preferred living pig's
centre, the high one if ``h > 0`` (``baselines.ballistic_angle``), turned by ``0.1 t``
rad (about 1 m at 10 m) to strike the structure under or above the pig; out of reach,
at 45 degrees. The observation is the game's.

Both have a vector form (``PoolCallShotVector``, ``SlingshotCallShotVector``) over the
batched vector envs, and registered ids (``impulse2d.envs.CALL_SHOT_IDS``)::

    env = gym.make("Pool2DCallShot-v0")             # one ball at random, five shots
    venv = gym.make_vec("Pool2DCallShot-v0", 512, vectorization_mode="vector_entry_point")

The ballistic player is a single action of Slingshot's space (the nearest pig, the low
arc, full speed, no trim); the ghost-ball player's pocket is one of Pool's, at its own
speed rule rather than the window's.

With ``obs_type="pixels"`` (both games) the observation is the game's image alone, no
features: what the call-shot action names (the pocket, the pig) must be read from the
frame, as a vision agent learns to (``Pool2DPixelsCallShot-v0``).

An action is computed from the game's current position (read from the game itself, not
from the last observation returned), so a position brought back with the wrapped env's
``restore_state`` is played from exactly.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium.vector.utils import batch_space

from . import pool, slingshot
from ._core import action_to_range, check_action, range_to_action
from ._gym import EnvState
from .baselines import ballistic_angle

__all__ = [
    "POOL_FEATURES",
    "PoolCallShot",
    "PoolCallShotVector",
    "SlingshotCallShot",
    "SlingshotCallShotVector",
    "pool_call_shot_actions",
    "pool_features",
    "pool_shots",
    "slingshot_call_shot_actions",
]

# -- pool: the geometry of the shots ------------------------------------------------------------
POCKETS = pool.pockets()[0]  # (6, 2) m
CUT_TRIM = 0.25  # most the trim moves sin(cut): 0.25 * 2r = 14 mm at the contact point
CLEARANCE_CAP = 3.0  # clearances are in ball diameters, capped here (nothing in the way)
REACH_CAP = 3.0  # m: longer than any distance on the bed (its diagonal is 2.84 m)
PER_POCKET = (
    "sin",
    "cos",
    "run",
    "reach",
    "clear_cue",
    "clear_ball",
    "pot_speed",
    "scratch_speed",
)
POOL_FEATURES = 4 + len(PER_POCKET) * len(POCKETS)


def _unit(v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    length = np.sqrt((v * v).sum(axis=-1))
    return v / np.maximum(length, 1e-9)[..., None], length


def pool_shots(cue: np.ndarray, ball: np.ndarray) -> dict[str, np.ndarray]:
    """The ghost-ball shot into each pocket, for cue balls and object balls ``(n, 2)``
    (m). For an object ball at ``b``, a pocket at ``q`` and the cue ball at ``c``::

        u_bp = (q - b) / |q - b|         the object ball's path to the pocket
        g = b - 2 r u_bp                 where the cue ball must be at contact
        u = (g - c) / |g - c|            the cue ball's path
        sin(cut) = u_bp x u,  cos(cut) = u . u_bp

    The cue ball's path passes the object ball's centre at the signed distance ``(b - c)
    x u = 2 r (u_bp x u) = 2 r sin(cut)`` (left positive). Returns ``ghost`` ``(n, 6,
    2)``, ``run`` (ball to pocket, m), ``reach`` (cue ball to ghost point, m), ``sin``
    and ``cos``, each ``(n, 6)``."""
    u_bp, run = _unit(POCKETS - ball[:, None, :])
    ghost = ball[:, None, :] - 2 * pool.BALL_RADIUS * u_bp
    u, reach = _unit(ghost - cue[:, None, :])
    sin = u_bp[..., 0] * u[..., 1] - u_bp[..., 1] * u[..., 0]
    cos = (u_bp * u).sum(axis=-1)
    return {"ghost": ghost, "run": run, "reach": reach, "sin": sin, "cos": cos}


def _clearance(
    start: np.ndarray, end: np.ndarray, xy: np.ndarray, obstacle: np.ndarray
) -> np.ndarray:
    """How far the nearest obstacle ball's centre is from each segment ``start -> end``
    (``(n, s, 2)`` each; ``xy`` ``(n, m, 2)``, ``obstacle`` ``(n, m)``, or ``(n, s, m)``
    for obstacles of each segment's own), in ball diameters, capped at
    ``CLEARANCE_CAP``: below 1, a ball rolling along the segment touches that obstacle."""
    d = end - start
    rel = xy[:, None, :, :] - start[:, :, None, :]  # (n, s, m, 2)
    length2 = np.maximum((d * d).sum(axis=-1), 1e-18)[..., None]
    t = np.clip((rel * d[:, :, None, :]).sum(axis=-1) / length2, 0.0, 1.0)
    gap = rel - t[..., None] * d[:, :, None, :]
    gap = np.sqrt((gap * gap).sum(axis=-1)) / (2 * pool.BALL_RADIUS)
    gap = np.where(obstacle if obstacle.ndim == 3 else obstacle[:, None, :], gap, CLEARANCE_CAP)
    if gap.shape[-1] == 0:
        return np.full(d.shape[:2], CLEARANCE_CAP)
    return np.minimum(gap.min(axis=-1), CLEARANCE_CAP)


CUSHION_BOX = (
    pool.TABLE_LENGTH / 2 - pool.BALL_RADIUS,
    pool.TABLE_WIDTH / 2 - pool.BALL_RADIUS,
)  # m: where a ball's centre meets a cushion
POCKET_RADII = pool.pockets()[1]
SCRATCH_CAP = 8.0  # m: a cue ball path traced this far without meeting a pocket is safe
BOUNCES = 3  # cushions the cue ball's path is traced off


def scratch_distance(start: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """How far (m) a ball rolling from ``start`` along ``direction`` (``(..., 2)``, unit)
    goes before its centre enters a pocket circle, its path reflected off the cushion
    lines (``CUSHION_BOX``) up to ``BOUNCES`` times; ``SCRATCH_CAP`` if it meets none.
    On each leg from ``p`` along ``d`` for a length ``t``, pocket ``q`` is met where the
    closest point ``p + s d`` (``s = clip((q - p) . d, 0, t)``) is within its radius."""
    half = np.array(CUSHION_BOX)
    p = np.clip(start, -half, half)
    d = direction.copy()
    travelled = np.zeros(start.shape[:-1])
    met = np.full(start.shape[:-1], SCRATCH_CAP)
    for _ in range(BOUNCES + 1):
        with np.errstate(divide="ignore", invalid="ignore"):
            to_wall = np.where(d > 0, (half - p) / d, np.where(d < 0, (-half - p) / d, np.inf))
        leg = np.maximum(to_wall.min(axis=-1), 0.0)
        rel = POCKETS - p[..., None, :]  # (..., 6, 2)
        s = np.clip((rel * d[..., None, :]).sum(axis=-1), 0.0, leg[..., None])
        miss = rel - s[..., None] * d[..., None, :]
        inside = np.sqrt((miss * miss).sum(axis=-1)) < POCKET_RADII
        first = np.where(inside, travelled[..., None] + s, SCRATCH_CAP).min(axis=-1)
        met = np.minimum(met, first)
        p = p + leg[..., None] * d
        travelled = travelled + leg
        bounce_x = to_wall[..., 0] <= to_wall[..., 1]
        d = np.where(np.stack([bounce_x, ~bounce_x], axis=-1), -d, d)
    return np.minimum(met, SCRATCH_CAP)


def speed_window(shot: dict[str, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Per pocket, the game's speed actions (``SPEED_RANGE`` on [-1, 1]) between which the
    ghost-ball shot pots the target and the cue ball stops short of a pocket, on the
    simplest model of the table: balls slow by the rolling resistance ``a`` (``v^2``
    falls by ``2 a`` per metre), the target leaves at ``(1 + e) / 2 cos(cut)`` of the cue
    ball's speed at contact, and the cue ball goes on at ``k`` of it, ``k = |u - (1 + e)
    / 2 (u . u_bp) u_bp|`` (the stun shot of two discs), along that direction, its path
    reflected off the cushions without loss (``scratch_distance``). The pot needs the
    target to roll its ``run``; the scratch comes once the cue ball rolls the path's
    distance ``D`` to a pocket:

        v_pot^2 = 2 a run / ((1 + e) / 2 cos)^2 + 2 a reach
        v_scratch^2 = 2 a D / k^2 + 2 a reach

    Both as actions, clipped to [-1, 1] (at 1 the limit is at or beyond full speed). The
    shots are into the six pockets of ``shot["ball"]`` ``(n, 2)``, or, given
    ``shot["pocket"]`` ``(n, s, 2)``, of the balls ``(n, s, 2)`` into those pockets."""
    a, half_e = pool.ROLLING_RESISTANCE, (1 + pool.RESTITUTION_BALL) / 2
    ball = shot["ball"] if "pocket" in shot else shot["ball"][:, None, :]
    u_bp, _ = _unit(shot.get("pocket", POCKETS) - ball)
    u, _ = _unit(shot["ghost"] - shot["cue"][:, None, :])
    after = u - half_e * (u * u_bp).sum(axis=-1, keepdims=True) * u_bp
    direction, k = _unit(after)
    leave = half_e * np.maximum(shot["cos"], 0.05)
    v_pot = np.sqrt(2 * a * shot["run"] / leave**2 + 2 * a * shot["reach"])
    distance = scratch_distance(shot["ghost"], direction)
    v_scratch = np.sqrt(2 * a * distance / np.maximum(k, 1e-3) ** 2 + 2 * a * shot["reach"])
    to_action = [range_to_action(v, pool.SPEED_RANGE) for v in (v_pot, v_scratch)]
    return tuple(np.clip(v, -1.0, 1.0) for v in to_action)  # type: ignore[return-value]


def pool_target_shots(observation: Any) -> dict[str, np.ndarray]:
    """Everything about the shots at the target (the object ball on the table nearest the
    cue ball), for Pool2D observations ``(n, 3 (k + 1))``: ``pool_shots``'s entries, the
    ``cue`` and ``ball`` positions ``(n, 2)``, ``has_target`` ``(n,)``, and the
    clearances ``(n, 6)`` of the cue ball's path to each ghost point (``clear_cue``) and
    of the target's path to each pocket (``clear_ball``). A table with no object ball
    left has no target (its numbers are then those of ball 1, and meaningless)."""
    xy, on_table = pool.ball_positions(observation)
    n = xy.shape[0]
    rows = np.arange(n)
    distance = np.sqrt(((xy[:, 1:] - xy[:, :1]) ** 2).sum(axis=-1))
    distance = np.where(on_table[:, 1:], distance, np.inf)
    index = np.argmin(distance, axis=1) + 1
    cue, ball = xy[:, 0], xy[rows, index]
    out = pool_shots(cue, ball)
    obstacle = on_table.copy()
    obstacle[:, 0] = False
    obstacle[rows, index] = False  # neither the cue ball nor the target is in the way
    starts = np.broadcast_to(cue[:, None, :], (n, len(POCKETS), 2))
    out["clear_cue"] = _clearance(starts, out["ghost"], xy, obstacle)
    starts = np.broadcast_to(ball[:, None, :], (n, len(POCKETS), 2))
    pockets = np.broadcast_to(POCKETS, (n, len(POCKETS), 2))
    out["clear_ball"] = _clearance(starts, pockets, xy, obstacle)
    out.update(cue=cue, ball=ball, has_target=np.isfinite(distance.min(axis=1)))
    out["pot_speed"], out["scratch_speed"] = speed_window(out)
    return out


def pool_features(observation: Any) -> np.ndarray:
    """``(n, POOL_FEATURES)`` float32: whether there is a target, its offset ``dx, dy``
    and distance from the cue ball (m), then per pocket the sine and cosine of the cut,
    the target's run to the pocket and the cue ball's reach to the ghost point (m), and
    the clearances of both paths (ball diameters, capped at 3); all 0 with no target."""
    shot = pool_target_shots(observation)
    offset = shot["ball"] - shot["cue"]
    distance = np.sqrt((offset * offset).sum(axis=1, keepdims=True))
    per_pocket = np.stack([shot[key] for key in PER_POCKET], axis=-1).reshape(len(offset), -1)
    has = shot["has_target"].astype(np.float64)[:, None]
    features = np.concatenate([has, offset, distance, per_pocket], axis=1) * has
    return features.astype(np.float32)


def _pool_feature_bounds() -> tuple[np.ndarray, np.ndarray]:
    per_low = {"sin": -1, "cos": -1, "run": 0, "reach": 0, "clear_cue": 0, "clear_ball": 0}
    per_low.update(pot_speed=-1, scratch_speed=-1)
    per_high = {"sin": 1, "cos": 1, "run": REACH_CAP, "reach": REACH_CAP}
    per_high.update(clear_cue=CLEARANCE_CAP, clear_ball=CLEARANCE_CAP)
    per_high.update(pot_speed=1, scratch_speed=1)
    low = [0.0, -REACH_CAP, -REACH_CAP, 0.0] + [per_low[k] for k in PER_POCKET] * len(POCKETS)
    high = [1.0, REACH_CAP, REACH_CAP, REACH_CAP] + [per_high[k] for k in PER_POCKET] * len(POCKETS)
    return np.array(low, np.float32), np.array(high, np.float32)


def pool_call_shot_actions(actions: Any, observation: Any) -> np.ndarray:
    """``(n, 8)`` call-shot actions (six pocket preferences, trim, speed; in [-1, 1]) and
    the Pool2D observations they answer -> ``(n, 2)`` game actions (float64): the
    ghost-ball line at the target into the preferred pocket, trimmed (module docstring).
    With no object ball left, the angle is 0."""
    a = np.asarray(actions, np.float64)
    shot = pool_target_shots(observation)
    pocket = np.argmax(a[:, : len(POCKETS)], axis=1)
    return called_shot(a[:, len(POCKETS) :], shot, shot["ball"], pocket)


def called_shot(
    trim_speed: np.ndarray, shot: dict[str, np.ndarray], ball: np.ndarray, called: np.ndarray
) -> np.ndarray:
    """``(n, 2)`` game actions: the cue ball at ``ball`` ``(n, 2)`` on the called shot
    (column ``called`` ``(n,)`` of ``shot``'s ``(n, s)`` arrays), its cut trimmed by
    ``trim_speed[:, 0]`` and its speed ``trim_speed[:, 1]`` in the called shot's window
    (module docstring); angle 0 where ``shot["has_target"]`` is false."""
    rows = np.arange(len(called))
    trim, s = trim_speed[:, 0], trim_speed[:, 1]
    sine = np.clip(shot["sin"][rows, called] + CUT_TRIM * trim, -1.0, 1.0)
    offset = ball - shot["cue"]
    distance = np.maximum(np.sqrt((offset * offset).sum(axis=1)), 1e-9)
    turn = np.arcsin(np.clip(2 * pool.BALL_RADIUS * sine / distance, -1.0, 1.0))
    angle = np.where(shot["has_target"], np.arctan2(offset[:, 1], offset[:, 0]) + turn, 0.0)
    angle = np.remainder(angle + math.pi, 2 * math.pi) - math.pi  # [-pi, pi): the game's scale
    speed = window_speed(s, shot["pot_speed"][rows, called], shot["scratch_speed"][rows, called])
    return np.stack([angle / math.pi, speed], axis=1)


def window_speed(s: np.ndarray, pot: np.ndarray, scratch: np.ndarray) -> np.ndarray:
    """The game's speed action for a call-shot speed ``s`` in [-1, 1], piecewise linear
    through three knots: ``s = -1`` is the pot speed of the called shot, ``s = 0`` the top
    of its window (the scratch speed; the pot speed where the window is empty), ``s = 1``
    full speed. Every speed that can pot is reachable, and "inside the window" is ``s <=
    0`` on every table, whatever the speeds themselves are."""
    top = np.maximum(scratch, pot)
    low = pot + (s + 1.0) * (top - pot)
    high = top + s * (1.0 - top)
    return np.clip(np.where(s <= 0.0, low, high), -1.0, 1.0)


# -- slingshot ----------------------------------------------------------------------------------
ANGLE_TRIM = 0.1  # rad: most the trim turns the launch


def slingshot_call_shot_actions(actions: Any, observation: Any) -> np.ndarray:
    """``(n, 7)`` call-shot actions (four pig preferences, arc, trim, speed; in [-1, 1])
    and the Slingshot2D observations they answer -> ``(n, 2)`` game actions (float64)
    (module docstring). With no pig left, 45 degrees."""
    a = np.asarray(actions, np.float64)
    obs = np.asarray(observation, np.float64).reshape(len(a), -1)
    slots = obs[:, :-1].reshape(len(a), -1, slingshot.FEATURES)[:, : slingshot.MAX_PIGS]
    alive = slots[..., 0] > 0.5
    target = np.argmax(np.where(alive, a[:, : slingshot.MAX_PIGS], -np.inf), axis=1)
    x, y = slingshot.slot_positions(slots[np.arange(len(a)), target])
    k = slingshot.MAX_PIGS
    speed = action_to_range(a[:, k + 2], slingshot.SPEED_RANGE)
    dx, dy = x - slingshot.SLING[0], y - slingshot.SLING[1]
    angle = ballistic_angle(dx, dy, speed, a[:, k] > 0) + ANGLE_TRIM * a[:, k + 1]
    angle = np.where(alive.any(axis=1), angle, math.pi / 4)
    angle_action = np.clip(range_to_action(angle, slingshot.ANGLE_RANGE), -1.0, 1.0)
    return np.stack([angle_action, a[:, k + 2]], axis=1)


# -- the wrappers -------------------------------------------------------------------------------
@dataclass(frozen=True)
class _Task:
    """What a call-shot wrapper needs of its game: the game class it wraps, the size of
    its action, the map to the game's action and the features it adds."""

    name: str
    game: type
    action_size: int
    to_game: Any  # (actions, observations) -> game actions
    features: Any = None  # observations -> (n, f) float32, or None
    feature_bounds: Any = None  # () -> (low, high)

    def observation_space(self, base: gym.spaces.Box) -> gym.spaces.Box:
        if self.features is None:
            return base
        low, high = self.feature_bounds()
        return gym.spaces.Box(
            np.concatenate([base.low, low]), np.concatenate([base.high, high]), dtype=np.float32
        )

    def observe(self, raw: np.ndarray) -> np.ndarray:
        """The call-shot observation of game observations ``(n, size)``."""
        if self.features is None:
            return raw
        return np.concatenate([raw, self.features(raw)], axis=1).astype(np.float32)

    def check(self, env: Any) -> Any:
        game = getattr(env.unwrapped, "game", None)
        if not isinstance(game, self.game):
            raise ValueError(
                f"env must be a {self.game.__name__[:-4]}2D env (gym.make of Pool2D-v0 or "
                f"Slingshot2D-v0), got {env.unwrapped!r}"
            )
        return game


POOL_TASK = _Task(
    "PoolCallShot", pool.PoolGame, 8, pool_call_shot_actions, pool_features, _pool_feature_bounds
)
SLINGSHOT_TASK = _Task("SlingshotCallShot", slingshot.SlingshotGame, 7, slingshot_call_shot_actions)


class _CallShot(gym.Wrapper):
    """A single env whose actions name the shot (see the module docstring)."""

    task: _Task

    def __init__(self, env: gym.Env) -> None:
        super().__init__(env)
        self._game = self.task.check(env)
        self._pixels = env.unwrapped.obs_type == "pixels"  # images pass as they are
        self.observation_space = (
            env.observation_space
            if self._pixels
            else self.task.observation_space(env.observation_space)
        )
        self.action_space = gym.spaces.Box(-1.0, 1.0, (self.task.action_size,), np.float32)

    def observation(self, raw: Any) -> np.ndarray:
        """The call-shot observation of one game observation."""
        if self._pixels:
            return raw
        return self.task.observe(np.asarray(raw, np.float32).reshape(1, -1))[0]

    def reset(self, **kwargs: Any) -> tuple[np.ndarray, dict[str, Any]]:
        obs, info = self.env.reset(**kwargs)
        return self.observation(obs), info

    def step(self, action: Any) -> tuple[np.ndarray, Any, Any, Any, dict[str, Any]]:
        action = check_action(action, self.action_space.shape)
        game_action = self.task.to_game(action[None], self._game.observe()[:1])[0]
        obs, reward, terminated, truncated, info = self.env.step(game_action.astype(np.float32))
        return self.observation(obs), reward, terminated, truncated, info

    def save_state(self) -> EnvState:
        """The game's ``save_state`` (``ShotEnv.save_state``)."""
        return self.env.unwrapped.save_state()

    def restore_state(self, state: EnvState) -> np.ndarray:
        """The game's ``restore_state``; returns the call-shot observation there."""
        return self.observation(self.env.unwrapped.restore_state(state))


class _CallShotVector(gym.vector.VectorWrapper):
    """A vector env whose actions name the shot (see the module docstring). In
    ``SAME_STEP`` autoreset mode, ``info["final_obs"]`` holds call-shot observations too."""

    task: _Task

    def __init__(self, env: gym.vector.VectorEnv) -> None:
        super().__init__(env)
        self._game = self.task.check(env)
        self._pixels = env.unwrapped.obs_type == "pixels"  # images pass as they are
        single = env.single_observation_space
        self.single_observation_space = (
            single if self._pixels else self.task.observation_space(single)
        )
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.single_action_space = gym.spaces.Box(-1.0, 1.0, (self.task.action_size,), np.float32)
        self.action_space = batch_space(self.single_action_space, self.num_envs)

    @property
    def autoreset_mode(self) -> Any:
        return self.env.unwrapped.autoreset_mode

    def observation(self, raw: Any) -> np.ndarray:
        """The call-shot observations of game observations ``(n, size)``."""
        if self._pixels:
            return raw
        return self.task.observe(np.asarray(raw, np.float32).reshape(len(raw), -1))

    def reset(self, **kwargs: Any) -> tuple[np.ndarray, dict[str, Any]]:
        obs, info = self.env.reset(**kwargs)
        return self.observation(obs), info

    def state_observation(self) -> np.ndarray:
        """``(num_envs, f)`` float32: what the state task observes of the worlds now (the
        game's state and the call-shot features), whatever this env observes; the labels
        a pixel encoder is pretrained on (``agents._pretrain``)."""
        return self.task.observe(self._game.observe())

    def state_observation_bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """The low and high bounds of each column of ``state_observation``."""
        base = gym.spaces.Box(self._game.observation_low, self._game.observation_high)
        space = self.task.observation_space(base)
        return space.low.astype(np.float64), space.high.astype(np.float64)

    def step(self, actions: Any) -> tuple[np.ndarray, Any, Any, Any, dict[str, Any]]:
        actions = check_action(actions, self.action_space.shape)
        game_actions = self.task.to_game(actions, self._game.observe())
        obs, reward, terminated, truncated, info = self.env.step(game_actions.astype(np.float32))
        if "final_obs" in info:
            final = info["final_obs"].copy()
            for i in np.flatnonzero(info["_final_obs"]):
                final[i] = self.observation(final[i][None])[0]
            info = {**info, "final_obs": final}
        return self.observation(obs), reward, terminated, truncated, info

    def save_state(self) -> EnvState:
        """The vector env's ``save_state`` (``ShotVectorEnv.save_state``)."""
        return self.env.unwrapped.save_state()

    def restore_state(self, state: EnvState, worlds: Any = None) -> np.ndarray:
        """The vector env's ``restore_state``; returns the call-shot observations."""
        return self.observation(self.env.unwrapped.restore_state(state, worlds))


class PoolCallShot(_CallShot):
    """Pool2D with the call-shot action and the shot features (module docstring)."""

    task = POOL_TASK


class PoolCallShotVector(_CallShotVector):
    """The batched Pool2D vector env with the call-shot action and features."""

    task = POOL_TASK


class SlingshotCallShot(_CallShot):
    """Slingshot2D with the call-shot action: name the pig and the arc."""

    task = SLINGSHOT_TASK


class SlingshotCallShotVector(_CallShotVector):
    """The batched Slingshot2D vector env with the call-shot action."""

    task = SLINGSHOT_TASK


# -- entry points of the registered ids ---------------------------------------------------------
def make_pool(**kwargs: Any) -> PoolCallShot:
    return PoolCallShot(pool.Pool2DEnv(**kwargs))


def make_pool_vector(**kwargs: Any) -> PoolCallShotVector:
    return PoolCallShotVector(pool.Pool2DVectorEnv(**kwargs))


def make_slingshot(**kwargs: Any) -> SlingshotCallShot:
    return SlingshotCallShot(slingshot.Slingshot2DEnv(**kwargs))


def make_slingshot_vector(**kwargs: Any) -> SlingshotCallShotVector:
    return SlingshotCallShotVector(slingshot.Slingshot2DVectorEnv(**kwargs))
