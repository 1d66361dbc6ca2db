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
