"""Shared helpers for the physics-law tests (``tests/test_physics_*.py``)."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

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
    contacts = world.last_contacts
    return 0 if contacts is None else int(contacts.size)


def upward_crossings(t: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Times at which ``x`` crosses zero going up, linearly interpolated."""
    i = np.flatnonzero((x[:-1] < 0.0) & (x[1:] >= 0.0))
    return t[i] + (t[i + 1] - t[i]) * (-x[i]) / (x[i + 1] - x[i])
