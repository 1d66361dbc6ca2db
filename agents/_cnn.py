"""A small convolutional encoder for the pixel tasks, sized for a 2-core CPU.

SB3's ``NatureCNN`` (the DQN paper's: 32 8x8/4, 64 4x4/2, 64 3x3/1, then 512) costs about
8.5 million multiply-adds a frame at 84 x 84; PPO runs it forward and back over every
sample of every epoch, which on two cores is most of a training run. ``ShotCNN`` keeps
its shape, three strided convolutions and a linear layer, at about a third of that: 16
5x5/2, 32 3x3/2, 32 3x3/2 and ``features_dim`` (256) outputs, ReLU throughout. A pool
ball is 1.5-2 pixels across at 64-84 pixels a side; the first layer's stride of 2 with
a 5 x 5 kernel keeps every ball inside some kernel's window at full resolution.

Named in a hyperparameter file as ``policy_kwargs: {features_extractor_class: ShotCNN}``
(``agents._config.FEATURE_EXTRACTORS``).
"""

from __future__ import annotations

import gymnasium as gym
import torch
from stable_baselines3.common.torch_layers import BaseFeaturesExtractor
from torch import nn


class ShotCNN(BaseFeaturesExtractor):
    """Three strided convolutions and a linear layer over channel-first images (SB3 has
    scaled them to [0, 1] and put channels first before they get here)."""

    def __init__(self, observation_space: gym.spaces.Box, features_dim: int = 256) -> None:
        super().__init__(observation_space, features_dim)
        channels = observation_space.shape[0]
        self.cnn = nn.Sequential(
            nn.Conv2d(channels, 16, 5, stride=2),
            nn.ReLU(),
            nn.Conv2d(16, 32, 3, stride=2),
            nn.ReLU(),
            nn.Conv2d(32, 32, 3, stride=2),
            nn.ReLU(),
            nn.Flatten(),
        )
        with torch.no_grad():
            flat = self.cnn(torch.zeros(1, *observation_space.shape)).shape[1]
        self.linear = nn.Sequential(nn.Linear(flat, features_dim), nn.ReLU())

    def forward(self, observations: torch.Tensor) -> torch.Tensor:
        return self.linear(self.cnn(observations))


class KeypointCNN(BaseFeaturesExtractor):
    """Where things are, for small objects on a still background (a pool table: the
    balls are 1.5-2 pixels across). Two convolutions that keep the image's layout (16
    5x5 stride 2, 32 3x3 stride 1, ReLU), then a *spatial softmax* per map (Levine, Finn,
    Darrell and Abbeel, 2016): each of the 32 maps ``a`` becomes the expected image
    position of where it fires,

        p_ij = exp(a_ij / T) / sum_kl exp(a_kl / T),   x = sum_ij p_ij x_j,   y = sum_ij p_ij y_i

    with ``x_j, y_i`` in [-1, 1] and a learnt temperature ``T``, alongside the map's
    maximum (whether it fires at all); those 96 numbers go through a linear layer to
    ``features_dim`` (ReLU). A flattening encoder must learn a position from which of
    its thousands of inputs lit up; here a position is a feature from the start."""

    def __init__(self, observation_space: gym.spaces.Box, features_dim: int = 128) -> None:
        super().__init__(observation_space, features_dim)
        channels = observation_space.shape[0]
        self.cnn = nn.Sequential(
            nn.Conv2d(channels, 16, 5, stride=2),
            nn.ReLU(),
            nn.Conv2d(16, 32, 3, stride=1),
        )
        with torch.no_grad():
            _, maps, height, width = self.cnn(torch.zeros(1, *observation_space.shape)).shape
        self.register_buffer("xs", torch.linspace(-1.0, 1.0, width).repeat(height))
        self.register_buffer("ys", torch.linspace(-1.0, 1.0, height).repeat_interleave(width))
        self.log_temperature = nn.Parameter(torch.zeros(()))
        self.linear = nn.Sequential(nn.Linear(3 * maps, features_dim), nn.ReLU())

    def keypoints(self, observations: torch.Tensor) -> torch.Tensor:
        """``(n, 3 maps)``: each map's expected ``x``, then ``y`` (in [-1, 1], left to
        right and top to bottom), then its maximum."""
        maps = self.cnn(observations).flatten(2)  # (n, maps, height * width)
        weights = torch.softmax(maps / self.log_temperature.exp(), dim=-1)
        return torch.cat([weights @ self.xs, weights @ self.ys, maps.amax(dim=-1)], dim=1)

    def forward(self, observations: torch.Tensor) -> torch.Tensor:
        return self.linear(self.keypoints(observations))
