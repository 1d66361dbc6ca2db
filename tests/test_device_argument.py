"""``World(device=...)``: ``'cpu'`` or ``'cuda'``; anything else, or ``'cuda'`` where it
cannot run, is refused with the rule or the reason (the GPU path itself: test_gpu.py)."""

from __future__ import annotations

import importlib.util

import numpy as np
import pytest

import impulse2d as p2


@pytest.mark.parametrize(
    "device", ["gpu", "CUDA", "cuda:0", None, 0, ["cpu"], np.array(["cpu", "cuda"]), b"cpu"]
)
def test_device_names_its_rule(device):
    with pytest.raises(ValueError, match=r"device must be one of 'cpu', 'cuda', got"):
        p2.World(device=device)


def test_cuda_where_it_cannot_run_says_why():
    if importlib.util.find_spec("numba_cuda") is None:
        reason = r"device='cuda' needs numba-cuda: pip install 'impulse2d\[gpu\]'"
    else:
        from numba import cuda

        if cuda.is_available():
            pytest.skip("this machine has a GPU")
        reason = "device='cuda' needs an NVIDIA GPU that numba-cuda can use, and found none"
    with pytest.raises(ValueError, match=reason):
        p2.World(device="cuda")


def test_the_default_and_copies_keep_the_device():
    world = p2.World()
    assert world.device == "cpu" and world.replicate(2).device == "cpu"
