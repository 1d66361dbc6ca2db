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

``pool_pockets``: ``pool_relative`` plus, for every object ball and each of the six
pockets, the direction from the ball to the pocket as a unit vector and the distance (m).
To pot ball ``b`` in pocket ``p`` the cue ball is sent at the "ghost ball" point
``b - 2 r u_bp`` (``u_bp`` the unit vector from the ball to the pocket, ``r`` the ball
radius), so the aim vector from the cue ball is ``(b - c) - 2 r u_bp``: linear in these
features once a pocket is chosen, and the ``direction_vector`` action takes its angle
from such a vector. With ``pool_relative`` alone the network must learn ``u_bp`` from
the absolute positions, and that approximation is what limited the aim's precision
(hyperparams/ppo.yml, run M). Which ball, which pocket, how hard (and whether a pocket
is blocked) are still learnt; the ghost point itself is not given.
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


class PoolPocketFeatures(PoolRelativeFeatures):
    """``pool_relative``'s features followed by, per object ball and pocket: the unit
    vector from the ball to the pocket and the distance in metres (0 for a potted ball)."""

    PER_POCKET = 3

    def __init__(self, observation_space: gym.spaces.Box) -> None:
        from impulse2d.envs.pool import pockets

        super().__init__(observation_space)
        centres = torch.as_tensor(pockets()[0], dtype=torch.float32)  # (6, 2) m
        self.register_buffer("pocket_centres", centres, persistent=False)
        self._features_dim += self.PER_POCKET * len(centres) * self.balls

    def forward(self, observations: torch.Tensor) -> torch.Tensor:
        relative = super().forward(observations)
        balls = observations.reshape(observations.shape[0], -1, 3)[:, 1:]
        scale = observations.new_tensor([_HALF_LENGTH, _HALF_WIDTH])
        xy = balls[:, :, :2] * scale  # (n, balls, 2) m
        on_table = (balls[:, :, 2:3] < 0.5).to(observations.dtype)[..., None]
        to_pocket = self.pocket_centres.to(observations.dtype) - xy[:, :, None, :]
        distance = torch.linalg.vector_norm(to_pocket, dim=-1, keepdim=True)
        unit = to_pocket / distance.clamp_min(1e-6)
        extra = torch.cat([unit, distance], dim=-1) * on_table  # (n, balls, 6, 3)
        return torch.cat([relative, extra.flatten(1)], dim=1)


EXTRACTORS: dict[str, Any] = {
    "pool_relative": PoolRelativeFeatures,
    "pool_pockets": PoolPocketFeatures,
}
