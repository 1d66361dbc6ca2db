"""The planners (``impulse2d.envs.planner``): what they simulate is what the env then
plays (bitwise: the float32 the action space hands on), planning leaves the env's
position untouched, the Pool planner clears a rack the ghost-ball player fouls in, the
Slingshot planner hits a pig, and bad arguments are refused by name."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import impulse2d  # noqa: F401  (registers the ids)
from impulse2d.envs.baselines import pool_ghost_ball
from impulse2d.envs.planner import PoolPlanner, SlingshotPlanner


def test_each_candidate_scores_what_the_env_then_gives():
    env = gym.make("Pool2D-v0")
    planner = PoolPlanner(env, candidates=32, position_weight=0.0)
    obs, _ = env.reset(seed=1000)
    for _ in range(6):
        actions = planner.candidate_actions(np.asarray(obs, np.float64))
        assert actions.dtype == np.float32 and actions.shape == (32, 2)
        scores = planner.play(actions)
        for k in (int(np.argmax(scores)), 5):  # the best and another
            saved = env.unwrapped.save_state()
            _, reward, *_ = env.step(actions[k])
            assert reward == scores[k]
            env.unwrapped.restore_state(saved)
        obs, _, terminated, truncated, _ = env.step(actions[int(np.argmax(scores))])
        if terminated or truncated:
            break


def test_planning_leaves_the_position_as_it_was():
    env = gym.make("Pool2D-v0", num_balls=3)
    obs, _ = env.reset(seed=3)
    before = env.unwrapped.game.world.snapshot().state.arrays()
    PoolPlanner(env, candidates=16)(obs)
    after = env.unwrapped.game.world.state.arrays()
    assert all(np.array_equal(before[k], after[k]) for k in before)


def _episode(env: gym.Env, act, seed: int) -> tuple[float, int]:
    obs, _ = env.reset(seed=seed)
    total, fouls, done = 0.0, 0, False
    while not done:
        obs, reward, terminated, truncated, info = env.step(act(obs))
        total, fouls = total + reward, fouls + int(info["fouls"])
        done = terminated or truncated
    return total, fouls


def test_it_clears_a_rack_the_ghost_ball_player_fouls_in():
    """Seed 1001's rack: the ghost-ball player fouls once (-1); the planner
    clears all 15 balls without a foul."""
    env = gym.make("Pool2D-v0")
    ghost, ghost_fouls = _episode(env, pool_ghost_ball, 1001)
    planned, planned_fouls = _episode(env, PoolPlanner(env, candidates=64), 1001)
    assert ghost_fouls > 0 and ghost < 15.0
    assert planned == 15.0 and planned_fouls == 0


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"candidates": 0}, "candidates must be in"),
        ({"speeds": (1.0, -1.0)}, "speeds must be"),
        ({"turns": (np.nan,)}, "turns must be finite"),
        ({"position_weight": -1.0}, "position_weight must be in"),
        ({"speeds": ()}, "speeds must be a non-empty sequence"),
        ({"speeds": 5.0}, "speeds must be a non-empty sequence"),
        ({"turns": "x"}, "turns must be"),
        ({"seed": -1}, "seed must be in"),
        ({"seed": 1.5}, "seed must be an int"),
    ],
)
def test_bad_arguments_are_refused_by_name(kwargs, message):
    with pytest.raises(ValueError, match=message):
        PoolPlanner(gym.make("Pool2D-v0"), **kwargs)


def test_it_plans_for_a_single_pool_env_only():
    with pytest.raises(ValueError, match="env must be a single Pool2D env"):
        PoolPlanner(gym.make("Slingshot2D-v0"))


def test_the_slingshot_planner_scores_what_the_env_then_gives():
    env = gym.make("Slingshot2D-v0", level="handmade")
    planner = SlingshotPlanner(env, candidates=24)
    obs, _ = env.reset(seed=4)
    actions = planner.candidate_actions(np.asarray(obs, np.float64))
    scores = planner.play(actions)
    best = int(np.argmax(scores))
    _, reward, *_ = env.step(actions[best])
    assert reward == scores[best] and reward >= scores.min()


def test_the_slingshot_planner_aims_at_the_pigs():
    """Its candidates are launches on the parabolas through the pigs: the one it picks
    on the first hand-made level destroys a pig."""
    env = gym.make("Slingshot2D-v0", level="handmade")
    obs, _ = env.reset(seed=0)
    planner = SlingshotPlanner(env, candidates=36)
    _, _, _, _, info = env.step(planner(obs))
    assert info["pigs_destroyed"] >= 1


def test_the_slingshot_planner_refuses_speeds_it_cannot_launch():
    with pytest.raises(ValueError, match="speeds must be in"):
        SlingshotPlanner(gym.make("Slingshot2D-v0"), speeds=(50.0,))
