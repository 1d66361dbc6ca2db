"""Shared helpers for the physics-law tests (``tests/test_physics_*.py``), the public-contract
tests (``tests/test_contract_*.py``) and the validation tests (``tests/test_validation_*.py``)."""

from __future__ import annotations

import re
from collections.abc import Callable
from contextlib import AbstractContextManager
from typing import Any

import numpy as np
import pytest

import impulse2d as p2

DT = 1.0 / 60.0
G = 9.81


def run(world: p2.World, seconds: float, dt: float = DT) -> None:
    """Step ``world`` for ``seconds`` of simulated time."""
    for _ in range(round(seconds / dt)):
        world.step(dt)


def trace(
    world: p2.World, seconds: float, probe: Callable[[], object], dt: float = DT
) -> tuple[np.ndarray, np.ndarray]:
    """Step for ``seconds``; return the times and ``probe()`` read after every step."""
    times, values = [], []
    for _ in range(round(seconds / dt)):
        world.step(dt)
        times.append(world.time)
        values.append(np.array(probe(), dtype=float))
    return np.array(times), np.array(values)


def contact_count(world: p2.World) -> int:
    """Number of contact points of the last step (0 if there were none)."""
    return world.contacts().size


def upward_crossings(t: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Times at which ``x`` crosses zero going up, linearly interpolated."""
    i = np.flatnonzero((x[:-1] < 0.0) & (x[1:] >= 0.0))
    return t[i] + (t[i + 1] - t[i]) * (-x[i]) / (x[i + 1] - x[i])


def steps(world: p2.World, n: int, dt: float = DT) -> None:
    """Step ``world`` ``n`` times."""
    for _ in range(n):
        world.step(dt)


def resting_circle_world(**world_kwargs: Any) -> tuple[p2.World, p2.Circle]:
    """A ``World(**world_kwargs)`` with a ground plane at y = 0 and a 1 kg ball of radius
    0.5 resting on it."""
    world = p2.World(**world_kwargs)
    world.add(p2.Plane(normal=(0.0, 1.0), point=(0.0, 0.0)))
    ball = world.add(p2.Circle(position=(0.0, 0.5), radius=0.5, mass=1.0))
    return world, ball


def names(parameter: str) -> AbstractContextManager[pytest.ExceptionInfo[ValueError]]:
    """pytest.raises(ValueError) whose message names ``parameter`` as a whole word."""
    return pytest.raises(ValueError, match=rf"(?<![\w]){re.escape(parameter)}(?![\w])")


def two_circles(**world_kwargs: Any) -> tuple[p2.World, p2.Circle, p2.Circle]:
    """A ``World(**world_kwargs)`` with two default circles, at (0, 0) and (3, 0)."""
    world = p2.World(**world_kwargs)
    a = world.add(p2.Circle(position=(0.0, 0.0)))
    b = world.add(p2.Circle(position=(3.0, 0.0)))
    return world, a, b
