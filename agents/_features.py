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

``pool_cuts``: ``pool_pockets`` plus, for every object ball and pocket, the sine and
cosine of the cut that pots the ball there: the angle between the cue ball's path to the
ghost point ``g = b - 2 r u_bp`` and the object ball's path ``u_bp`` to the pocket. The
line from the cue ball to ``g`` passes the ball's centre at the signed distance

    (b - c) x u = (|g - c| u + 2 r u_bp) x u = 2 r (u_bp x u),    u = (g - c) / |g - c|,

so ``sin(cut) = u_bp x u`` (left of the ball positive) is exactly the ``tanh(b)`` of the
``ball_contact`` action that plays the ghost-ball shot into that pocket, and ``cos(cut)``
(``u . u_bp``) says how thin, hence how hard to make, that shot is. With them, aiming at
a chosen pocket is linear in the input (up to the ``atanh`` of the action's squashing);
which pocket, and how hard, is what is left to learn. This is the geometry a player reads
off the table; whether the paths are clear is not given.

``pool_target``: the observation plus the shots the ``pocket_choice`` action can play:
at the target ball (the nearest object ball on the table), whether there is one, its
offset and distance from the cue ball, and per pocket the sine and cosine of the cut,
the object ball's run to the pocket and the cue ball's to the ghost point (m), and how
clear both paths are (the nearest other ball's distance from each, in ball diameters,
capped at 3: below 1 a ball on that path hits it). The numbers come from
``_pool_geometry``, as the action's do.
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import torch
from stable_baselines3.common.torch_layers import BaseFeaturesExtractor

from impulse2d.envs.pool import pockets

# HALF_SIZE: Pool2D's observation scale, x / (L/2) and y / (W/2).
from ._pool_geometry import HALF_SIZE, balls, shots, target_shots


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
        scale = observations.new_tensor(HALF_SIZE)
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
        super().__init__(observation_space)
        centres = torch.as_tensor(pockets()[0], dtype=torch.float32)  # (6, 2) m
        self.register_buffer("pocket_centres", centres, persistent=False)
        self._features_dim += self.PER_POCKET * len(centres) * self.balls

    def forward(self, observations: torch.Tensor) -> torch.Tensor:
        relative = super().forward(observations)
        balls = observations.reshape(observations.shape[0], -1, 3)[:, 1:]
        scale = observations.new_tensor(HALF_SIZE)
        xy = balls[:, :, :2] * scale  # (n, balls, 2) m
        on_table = (balls[:, :, 2:3] < 0.5).to(observations.dtype)[..., None]
        to_pocket = self.pocket_centres.to(observations.dtype) - xy[:, :, None, :]
        distance = torch.linalg.vector_norm(to_pocket, dim=-1, keepdim=True)
        unit = to_pocket / distance.clamp_min(1e-6)
        extra = torch.cat([unit, distance], dim=-1) * on_table  # (n, balls, 6, 3)
        return torch.cat([relative, extra.flatten(1)], dim=1)


class PoolCutFeatures(PoolPocketFeatures):
    """``pool_pockets``'s features followed by, per object ball and pocket: the sine
    (signed, left positive) and cosine of the cut that pots the ball in that pocket
    (0 for a potted ball)."""

    PER_CUT = 2

    def __init__(self, observation_space: gym.spaces.Box) -> None:
        super().__init__(observation_space)
        self._features_dim += self.PER_CUT * len(self.pocket_centres) * self.balls

    def forward(self, observations: torch.Tensor) -> torch.Tensor:
        pockets = super().forward(observations)
        xy, on_table = balls(observations)
        n, k = xy.shape[0], xy.shape[1] - 1
        cue = xy[:, :1].expand(-1, k, -1).reshape(n * k, 2)
        shot = shots(cue, xy[:, 1:].reshape(n * k, 2))  # every object ball, each pocket
        cuts = torch.stack([shot["sin"], shot["cos"]], dim=-1).reshape(n, k, -1, 2)
        extra = cuts * on_table[:, 1:, None, None].to(observations.dtype)
        return torch.cat([pockets, extra.flatten(1)], dim=1)


class PoolTargetFeatures(BaseFeaturesExtractor):
    """The Pool2D observation followed by: has a target, its dx, dy and distance from the
    cue ball (m), then per pocket: sin and cos of the cut, run and reach (m), clearance of
    the cue ball's and the object ball's paths (ball diameters); zeros with no target."""

    PER_POCKET = 6

    def __init__(self, observation_space: gym.spaces.Box) -> None:
        size = int(observation_space.shape[0])
        if size % 3 or size < 6:
            raise ValueError(f"pool_target needs a Pool2D observation, got size {size}")
        super().__init__(observation_space, size + 4 + 6 * self.PER_POCKET)

    def forward(self, observations: torch.Tensor) -> torch.Tensor:
        shot = target_shots(observations)
        offset = shot["ball"] - shot["cue"]
        distance = torch.linalg.vector_norm(offset, dim=1, keepdim=True)
        keys = ("sin", "cos", "run", "reach", "clear_cue", "clear_ball")
        per_pocket = torch.stack([shot[key] for key in keys], dim=-1).flatten(1)
        has = shot["has_target"].to(observations.dtype)[:, None]
        extra = torch.cat([has, offset, distance, per_pocket], dim=1) * has
        return torch.cat([observations, extra.to(observations.dtype)], dim=1)


EXTRACTORS: dict[str, Any] = {
    "pool_relative": PoolRelativeFeatures,
    "pool_pockets": PoolPocketFeatures,
    "pool_cuts": PoolCutFeatures,
    "pool_target": PoolTargetFeatures,
}
