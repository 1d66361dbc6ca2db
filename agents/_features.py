"""Optional feature extractors: the observation plus quantities derived from it.

Selected in a hyperparameter file by name, e.g. ``policy_kwargs: {features_extractor_class:
pool_relative}``; the env and its observation are unchanged, the network computes these
features itself as its first layer.

``pool_relative``: Pool2D observations are absolute ball positions, but a shot is aimed
along the line from the cue ball to a ball, and the action's direction is an absolute
angle ``pi * action[0]``. To aim, a plain MLP must learn ``atan2`` of differences of its
inputs, from shots that touch a ball, which are rare at first; meanwhile the easy lesson
("hit softly: hard shots scratch") pulls the speed down until hardly a shot reaches a ball.
This extractor adds, for every object ball, its offset from the cue ball in metres, the
distance, and the direction as a unit vector and as an angle on the action's scale
(``atan2(dy, dx) / pi``, 0 for a potted ball), so that "aim at the ball" is a short
step for the network. Where to aim on the ball (the cut), how hard to hit and which ball
to play are still learnt.
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import torch
from stable_baselines3.common.torch_layers import BaseFeaturesExtractor

# Pool2D's observation scale: x / (length / 2), y / (width / 2) (see Pool2DEnv).
_HALF_LENGTH, _HALF_WIDTH = 1.27, 0.635


class PoolRelativeFeatures(BaseFeaturesExtractor):
    """The Pool2D observation followed by, per object ball: dx, dy (m), distance (m),
    cos and sin of the direction, direction / pi (all 0 for a potted ball)."""

    PER_BALL = 6

    def __init__(self, observation_space: gym.spaces.Box) -> None:
        size = int(observation_space.shape[0])
        if size % 3 or size < 6:
            raise ValueError(f"pool_relative needs a Pool2D observation, got size {size}")
        self.balls = size // 3 - 1
        super().__init__(observation_space, size + self.PER_BALL * self.balls)

    def forward(self, observations: torch.Tensor) -> torch.Tensor:
        balls = observations.reshape(observations.shape[0], -1, 3)
        scale = observations.new_tensor([_HALF_LENGTH, _HALF_WIDTH])
        xy = balls[:, :, :2] * scale
        offset = xy[:, 1:] - xy[:, :1]  # object balls relative to the cue ball
        on_table = (balls[:, 1:, 2:3] < 0.5).to(observations.dtype)
        distance = torch.linalg.vector_norm(offset, dim=-1, keepdim=True)
        unit = offset / distance.clamp_min(1e-6)
        angle = torch.atan2(offset[..., 1:2], offset[..., 0:1]) / torch.pi
        extra = torch.cat([offset, distance, unit, angle], dim=-1) * on_table
        return torch.cat([observations, extra.flatten(1)], dim=1)


EXTRACTORS: dict[str, Any] = {"pool_relative": PoolRelativeFeatures}
