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
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import gymnasium as gym
import numpy as np
from stable_baselines3.common.vec_env import VecEnv, VecEnvWrapper


def direction_vector(actions: np.ndarray) -> np.ndarray:
    """``(n, 3)`` policy outputs ``(u, v, s)`` -> ``(n, 2)`` env actions."""
    actions = np.asarray(actions, np.float64)
    angle = np.arctan2(actions[:, 1], actions[:, 0]) / np.pi
    return np.stack([angle, np.tanh(actions[:, 2])], axis=1).astype(np.float32)


BOUND = 5.0
TRANSFORMS: dict[str, tuple[int, Callable[[np.ndarray], np.ndarray]]] = {
    # name: (policy action size, policy actions -> env actions)
    "direction_vector": (3, direction_vector),
}


class TransformAction(VecEnvWrapper):
    """A VecEnv whose actions are mapped by a named transform before the env sees them.
    Its action space is [-5, 5]: SB3 needs finite bounds and clips to them, and the
    transform's ``tanh`` is flat beyond (tanh 5 = 0.9999), so the clip changes nothing."""

    def __init__(self, venv: VecEnv, name: str) -> None:
        size, self.transform = TRANSFORMS[name]
        space = gym.spaces.Box(-BOUND, BOUND, (size,), np.float32)
        super().__init__(venv, action_space=space)

    def step_async(self, actions: np.ndarray) -> None:
        self.venv.step_async(self.transform(actions))

    def step_wait(self) -> Any:
        return self.venv.step_wait()

    def reset(self) -> Any:
        return self.venv.reset()
