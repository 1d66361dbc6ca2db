"""The image encoders of agents._cnn: output sizes for the pixel task's frames, gradients
reaching every layer, and the spatial softmax's positions worked by hand."""

from __future__ import annotations

import math

import gymnasium as gym
import pytest

torch = pytest.importorskip("torch")
from agents._cnn import KeypointCNN, ShotCNN  # noqa: E402

FRAMES = gym.spaces.Box(0.0, 1.0, (3, 64, 64))


@pytest.mark.parametrize(("encoder", "size"), [(ShotCNN, 256), (KeypointCNN, 128)])
def test_an_encoder_gives_its_features_and_learns_in_every_layer(encoder, size):
    model = encoder(FRAMES)
    features = model(torch.rand(5, 3, 64, 64))
    assert features.shape == (5, size) and model.features_dim == size
    features.sum().backward()
    assert all(p.grad is not None and p.grad.abs().sum() > 0 for p in model.parameters())


def test_the_spatial_softmax_finds_a_lit_pixel():
    """Both convolutions set to pass channel 0 straight through (a 1 at the kernel's
    centre): map 0's pixel (j, i) is input pixel (2 j + 4, 2 i + 4). A lit input pixel
    at (24, 44) is map pixel (10, 20) of 28 x 28, so with a sharp softmax its keypoint
    is x = -1 + 2 * 20 / 27, y = -1 + 2 * 10 / 27; its maximum is the pixel's value."""
    model = KeypointCNN(FRAMES)
    with torch.no_grad():
        for layer, centre in ((model.cnn[0], 2), (model.cnn[2], 1)):
            layer.weight.zero_()
            layer.bias.zero_()
            layer.weight[0, 0, centre, centre] = 1.0
        model.log_temperature.fill_(math.log(0.005))
        image = torch.zeros(1, 3, 64, 64)
        image[0, 0, 24, 44] = 1.0
        points = model.keypoints(image)[0]
    maps = 32
    assert points[0].item() == pytest.approx(-1 + 2 * 20 / 27, abs=1e-4)
    assert points[maps].item() == pytest.approx(-1 + 2 * 10 / 27, abs=1e-4)
    assert points[2 * maps].item() == pytest.approx(1.0)
    # a map that never fires spreads evenly: its keypoint is the centre
    assert points[1].item() == pytest.approx(0.0, abs=1e-6)
