"""The agents' Slingshot2D action transform against the launches it claims: the ballistic
player is one of its actions, the arc, trim and speed do what they say, and a dead pig
cannot be chosen."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest

import impulse2d  # noqa: F401  (registers the env ids)
from impulse2d.envs import slingshot
from impulse2d.envs.baselines import ballistic_angle, slingshot_ballistic


def _level(name: str) -> np.ndarray:
    obs, _ = gym.make("Slingshot2D-v0", level=name).reset(seed=0)
    return obs[None]


def _named(pig: int, arc: float = -1.0, trim: float = 0.0, speed: float = 5.0) -> np.ndarray:
    action = np.full((1, 7), -1.0)
    action[0, pig], action[0, 4:] = 1.0, (arc, trim, speed)
    return action


def _pigs(obs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    slots = obs[0, :-1].reshape(-1, slingshot.FEATURES)[: slingshot.MAX_PIGS].astype(np.float64)
    return slingshot.slot_positions(slots)


def test_the_ballistic_players_launches_are_target_choice_actions() -> None:
    from agents._wrappers import target_choice

    obs = _level("twin-towers")  # two pigs
    x, _ = _pigs(obs)
    nearest = int(np.argmin(np.where(x > 0, x, np.inf)))
    for arc, which in ((-1.0, "low"), (1.0, "high")):
        got = target_choice(_named(nearest, arc, speed=20.0), obs)[0]
        assert np.allclose(got, slingshot_ballistic(obs[0], which), atol=1e-6)


def test_arc_trim_and_speed_set_the_launch() -> None:
    from agents._wrappers import ANGLE_TRIM, target_choice

    obs = _level("twin-towers")
    x, y = _pigs(obs)
    lo, hi = slingshot.SPEED_RANGE
    speed_action = np.tanh(0.3)
    speed = lo + 0.5 * (speed_action + 1) * (hi - lo)
    for pig in (0, 1):
        dx, dy = x[pig] - slingshot.SLING[0], y[pig] - slingshot.SLING[1]
        for arc in (-1.0, 1.0):
            want = float(ballistic_angle(dx, dy, speed, arc > 0)) + ANGLE_TRIM * np.tanh(0.7)
            got = target_choice(_named(pig, arc, 0.7, 0.3), obs)[0]
            assert got[0] == pytest.approx(4 * want / math.pi - 1, abs=1e-6)  # 0-90 degrees
            assert got[1] == pytest.approx(speed_action, abs=1e-6)
            # the launch passes through the pig's centre without the trim (drag-free)
            angle = float(ballistic_angle(dx, dy, speed, arc > 0))
            t = dx / (speed * math.cos(angle))
            assert speed * math.sin(angle) * t - 9.81 * t * t / 2 == pytest.approx(dy, abs=1e-9)


def test_dead_pigs_cannot_be_chosen_and_a_cleared_level_gives_45_degrees() -> None:
    from agents._wrappers import target_choice

    obs = _level("twin-towers")
    dead = obs.copy()
    dead[0, : slingshot.FEATURES] = 0.0  # pig 0 destroyed: its slot reads as zeros
    prefers_dead = _named(0)
    prefers_dead[0, 1] = 0.5  # pig 1 is second best
    assert np.array_equal(target_choice(prefers_dead, dead), target_choice(_named(1), obs))
    cleared = obs.copy()
    cleared[0, : slingshot.FEATURES * slingshot.MAX_PIGS] = 0.0
    assert target_choice(_named(2, trim=3.0), cleared)[0, 0] == pytest.approx(0.0, abs=1e-7)
