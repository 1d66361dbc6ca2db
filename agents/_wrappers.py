"""Optional action transforms between the policy and the env (the env is unchanged).

Selected by the run key ``action_transform`` of a hyperparameter entry; training wraps the
vector env in ``TransformAction`` and evaluation applies the same function to the trained
policy's output, so the agent is always scored on the env's own actions.

``direction_vector``: the policy gives ``(u, v, s)`` (in [-5, 5]) and the env gets
``(atan2(v, u) / pi, tanh(s))``. Two lessons from tuning Pool2D (hyperparams/ppo.yml):

* Pool2D's direction is an angle ``pi * action[0]`` with a seam at +-1 (both are "towards
  -x"): a Gaussian policy aiming near the seam puts half its samples on the far side, and a
  network must draw ``atan2`` with a jump in it. As a 2-vector the direction has no seam,
  and with ``pool_relative`` features "aim at the ball" is the unit vector to it, a linear
  function of the inputs.
* Early on, when most shots miss, hard shots mostly scratch (-1), so the speed falls; with
  actions clipped to [-1, 1] its mean sinks below -1, where every sample is the same
  gentlest stroke and the gradient that would raise the speed again, once the aim is
  good, is gone. ``tanh`` keeps a slope there.

``ball_contact`` (Pool2D): the policy gives ``(b, s)`` and the cue ball is sent at the
nearest object ball still on the table, passing its centre at the signed distance
``2 r tanh(b)`` (``r`` the ball radius): ``b = 0`` is a full-ball hit, ``tanh(b) = +-1``
the thinnest cut to the left or right. With ``theta`` the direction and ``d`` the distance
from the cue ball to that ball, the env's angle is

    phi = theta + asin(clip(2 r tanh(b) / d, -1, 1)),

since a line at angle ``phi`` from the cue ball passes the ball's centre at
``d sin(phi - theta)``. This is the egocentric action a player thinks in ("how thin, how
hard"), meant to fix what limited ``direction_vector`` (hyperparams/ppo.yml, run M):
there the ghost-ball aim differs from "at the ball" by ``asin(2 r sin(cut) / d)``, a few
degrees, which must come out of an absolute direction learnt to that precision; here the
ghost-ball shot is ``tanh(b) = sin(cut)`` (the cut angle between the cue ball's line and
the object ball's line to the pocket), a number of order one. Every sample touches the
ball, so "hit softly" is not the first lesson. It helped (0.81-0.85 against 0.55 at
150,000 shots, runs N-Q) but stopped short of the ghost-ball player, for the reason given
under ``pocket_choice``. Only the nearest ball can be played, and no shot misses on
purpose.

``pocket_choice`` (Pool2D): the player calls the pocket. The policy gives eight numbers:
six pocket preferences, a cut correction ``c`` and a speed ``s``. The target is, as for
``ball_contact``, the nearest object ball on the table; the pocket is the one with the
highest preference, and the cue ball passes the target's centre at

    2 r clip(sin(cut_p) + 0.25 tanh(c), -1, 1),

``sin(cut_p)`` being the ghost-ball cut into that pocket (``_pool_geometry``): ``c = 0``
plays the ghost-ball line, and ``c`` trims it (by up to 14 mm at the contact point) for
throw and the pocket's jaws. This is a parameterized action (Hausknecht and Stone,
"Deep reinforcement learning in parameterized action space", 2016: a choice made by the
argmax of continuous preferences, each with its own parameters), which a Gaussian
policy explores as it explores any number. What ``ball_contact`` left to the network
and it learnt poorly (hyperparams/ppo.yml, runs N-Q) is the exact ``sin(cut)`` of
whichever pocket it meant, a function with a jump wherever the best pocket changes: a
128 x 128 MLP regressing the ghost-ball player's contact point from ``pool_cuts``
features, in plain supervised learning on 22,000 tables, still missed by 0.06 (median;
0.26 at the 90th percentile) where a pot needs about 0.03. Here the jump is the argmax's,
and the network's outputs are smooth preferences. Which pocket, the trim and the speed
(the ghost-ball player's fixed rule scratches on 6 % of its shots) are learnt. The
``pool_target`` features describe the same shots.

``target_choice`` (Slingshot2D): the player names a pig and an arc. The policy gives
seven numbers: four pig preferences, an arc ``h``, an angle trim ``t`` and a speed
``s``. The bird is launched at ``v`` (``s`` on the env's speed scale) along the
drag-free parabola through the preferred pig's centre, the high one if ``h > 0``
(``impulse2d.envs.baselines.ballistic_angle``), turned by ``0.1 tanh(t)`` rad (about
1 m up or down at 10 m) to hit the structure under or above a pig. Out of reach at
``v``, the launch is at 45 degrees. The ballistic player is one of these actions (the
nearest pig, the low arc, full speed, no trim); which pig, which arc, how fast and the
trim are learnt.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import gymnasium as gym
import numpy as np
import torch
from stable_baselines3.common.vec_env import VecEnv, VecEnvWrapper

from impulse2d.envs.pool import BALL_RADIUS


def direction_vector(actions: np.ndarray, obs: np.ndarray | None = None) -> np.ndarray:
    """``(n, 3)`` policy outputs ``(u, v, s)`` -> ``(n, 2)`` env actions (``obs`` unused)."""
    actions = np.asarray(actions, np.float64)
    angle = np.arctan2(actions[:, 1], actions[:, 0]) / np.pi
    return np.stack([angle, np.tanh(actions[:, 2])], axis=1).astype(np.float32)


def _rows(obs: Any, count: int) -> np.ndarray:
    """Observations as ``count`` float64 rows (one observation may come unbatched)."""
    return np.asarray(obs, np.float64).reshape(count, -1)


def ball_contact(actions: np.ndarray, obs: np.ndarray) -> np.ndarray:
    """``(n, 2)`` policy outputs ``(b, s)`` and ``(n, 3k)`` Pool2D observations -> ``(n, 2)``
    env actions: aim past the nearest object ball on the table at ``2 r tanh(b)`` from its
    centre (see the module docstring). With no object ball left, the angle is 0."""
    from ._pool_geometry import balls, target_ball

    a = torch.as_tensor(np.asarray(actions, np.float64))
    xy, on_table = balls(torch.as_tensor(_rows(obs, len(a))))
    index, has_target = target_ball(xy, on_table)
    ball = xy[torch.arange(xy.shape[0]), index]
    return _past_the_ball(xy[:, 0], ball, has_target, torch.tanh(a[:, 0]), a[:, 1])


def _past_the_ball(
    cue: torch.Tensor, ball: torch.Tensor, has_target: torch.Tensor, sine: torch.Tensor,
    speed: torch.Tensor,
) -> np.ndarray:  # fmt: skip
    """Env actions: the cue ball sent so that its path passes ``ball``'s centre at
    ``2 r sine`` (left positive), at the speed action ``tanh(speed)``; angle 0 where
    there is no target. A line at ``phi`` passes the centre at ``d sin(phi - theta)``."""
    offset = ball - cue
    distance = torch.linalg.vector_norm(offset, dim=1).clamp_min(1e-9)
    turn = torch.asin((2 * BALL_RADIUS * sine / distance).clamp(-1, 1))
    angle = torch.atan2(offset[:, 1], offset[:, 0]) + turn
    angle = torch.where(has_target, angle, 0.0)
    angle = (angle + torch.pi) % (2 * torch.pi) - torch.pi  # back to [-pi, pi): the env's scale
    out = torch.stack([angle / torch.pi, torch.tanh(speed)], dim=1)
    return out.numpy().astype(np.float32)


CUT_CORRECTION = 0.25  # most the correction moves sin(cut): 0.25 * 2r = 14 mm at contact


def pocket_choice(actions: np.ndarray, obs: np.ndarray) -> np.ndarray:
    """``(n, 8)`` policy outputs (six pocket preferences, cut correction, speed) and
    ``(n, 3k)`` Pool2D observations -> ``(n, 2)`` env actions: the ghost-ball shot at the
    nearest object ball into the preferred pocket, trimmed (see the module docstring).
    With no object ball left, the angle is 0."""
    from ._pool_geometry import target_shots

    a = torch.as_tensor(np.asarray(actions, np.float64))
    shot = target_shots(torch.as_tensor(_rows(obs, len(a))))
    pocket = torch.argmax(a[:, :6], dim=1)
    sine = shot["sin"][torch.arange(a.shape[0]), pocket] + CUT_CORRECTION * torch.tanh(a[:, 6])
    return _past_the_ball(shot["cue"], shot["ball"], shot["has_target"], sine.clamp(-1, 1), a[:, 7])


ANGLE_TRIM = 0.1  # rad: most the trim turns the launch


def target_choice(actions: np.ndarray, obs: np.ndarray) -> np.ndarray:
    """``(n, 7)`` policy outputs (four pig preferences, arc, trim, speed) and ``(n, 217)``
    Slingshot2D observations -> ``(n, 2)`` env actions (see the module docstring). With no
    pig left, 45 degrees."""
    from impulse2d.envs import slingshot
    from impulse2d.envs.baselines import ballistic_angle

    actions = np.asarray(actions, np.float64)
    slots = _rows(obs, len(actions))[:, :-1].reshape(len(actions), -1, slingshot.FEATURES)
    pigs = slots[:, : slingshot.MAX_PIGS]
    alive = pigs[..., 0] > 0.5
    target = np.argmax(np.where(alive, actions[:, : slingshot.MAX_PIGS], -np.inf), axis=1)
    x, y = slingshot.slot_positions(pigs[np.arange(len(actions)), target])
    lo, hi = slingshot.SPEED_RANGE
    speed_action = np.tanh(actions[:, 6])
    speed = lo + 0.5 * (speed_action + 1.0) * (hi - lo)
    dx, dy = x - slingshot.SLING[0], y - slingshot.SLING[1]
    angle = ballistic_angle(dx, dy, speed, actions[:, 4] > 0)
    angle = np.where(alive.any(axis=1), angle + ANGLE_TRIM * np.tanh(actions[:, 5]), np.pi / 4)
    lo, hi = slingshot.ANGLE_RANGE
    angle_action = np.clip(2 * (angle - lo) / (hi - lo) - 1, -1.0, 1.0)
    return np.stack([angle_action, speed_action], axis=1).astype(np.float32)


BOUND = 5.0
Transform = Callable[[np.ndarray, np.ndarray], np.ndarray]
TRANSFORMS: dict[str, tuple[int, Transform]] = {
    # name: (policy action size, (policy actions, observations) -> env actions)
    "direction_vector": (3, direction_vector),
    "ball_contact": (2, ball_contact),
    "pocket_choice": (8, pocket_choice),
    "target_choice": (7, target_choice),
}


class TransformAction(VecEnvWrapper):
    """A VecEnv whose actions are mapped by a named transform before the env sees them.
    Its action space is [-5, 5]: SB3 needs finite bounds and clips to them, and the
    transform's ``tanh`` is flat beyond (tanh 5 = 0.9999), so the clip changes nothing.
    It keeps the latest observation, which is what the policy acted on (SB3's VecEnv
    returns the next episode's first observation where one ended)."""

    def __init__(self, venv: VecEnv, name: str) -> None:
        size, self.transform = TRANSFORMS[name]
        space = gym.spaces.Box(-BOUND, BOUND, (size,), np.float32)
        super().__init__(venv, action_space=space)
        self.last_obs: np.ndarray | None = None

    def step_async(self, actions: np.ndarray) -> None:
        if self.last_obs is None:
            raise RuntimeError("TransformAction: reset() before step()")
        self.venv.step_async(self.transform(actions, self.last_obs))

    def step_wait(self) -> Any:
        obs, rewards, dones, infos = self.venv.step_wait()
        self.last_obs = obs
        return obs, rewards, dones, infos

    def reset(self) -> Any:
        self.last_obs = self.venv.reset()
        return self.last_obs
