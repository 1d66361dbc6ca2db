"""Copies and pickles of every env behave exactly as the original: single and vector
envs of both games, copied mid-episode, then stepped with the same actions as the
original, give bitwise the same observations, rewards, flags and infos (what planners
and rollouts from a position rely on). The engine's ``World`` likewise."""

from __future__ import annotations

import copy
import pickle
from typing import Any

import gymnasium as gym
import numpy as np
import pytest

import impulse2d as p2
from bitwise import same_bitwise

CASES = [
    ("Pool2D-v0", {"num_balls": 1}),
    ("Pool2D-v0", {}),  # the 15-ball rack
    ("Slingshot2D-v0", {}),  # random levels
]


def _make(env_id: str, kwargs: dict[str, Any], vector: bool) -> Any:
    if vector:
        return gym.make_vec(env_id, 3, vectorization_mode="vector_entry_point", **kwargs)
    return gym.make(env_id, **kwargs)


@pytest.mark.parametrize("vector", [False, True], ids=["single", "vector"])
@pytest.mark.parametrize(("env_id", "kwargs"), CASES, ids=["pool-1", "pool-15", "slingshot"])
def test_a_copy_or_pickle_plays_on_exactly_as_the_original(env_id, kwargs, vector):
    env = _make(env_id, kwargs, vector)
    env.reset(seed=4)
    rng = np.random.default_rng(0)
    shape = (3, 2) if vector else (2,)
    env.step(rng.uniform(-1, 1, shape).astype(np.float32))  # mid-episode
    copies = [copy.deepcopy(env), pickle.loads(pickle.dumps(env))]
    for _ in range(4):
        action = rng.uniform(-1, 1, shape).astype(np.float32)
        reference = env.step(action)
        for other in copies:
            assert same_bitwise(list(other.step(action)), list(reference))
    copies[0].reset(seed=9)  # the copies are their own: resetting one leaves the others
    action = rng.uniform(-1, 1, shape).astype(np.float32)
    assert same_bitwise(list(copies[1].step(action)), list(env.step(action)))


def test_a_world_copy_has_its_own_state_and_replays_the_original():
    world = p2.World()
    ball = world.add(p2.Circle(position=(0.0, 1.0), radius=0.5, restitution=0.5))
    world.add(p2.Plane())
    for _ in range(30):
        world.step(1 / 60)
    twin, thawed = copy.deepcopy(world), pickle.loads(pickle.dumps(world))
    assert not np.shares_memory(twin.state.body, world.state.body)
    twin.bodies[0].velocity = (3.0, 0.0)  # changes the copy only, through its own view
    assert tuple(ball.velocity) != (3.0, 0.0)
    for _ in range(60):
        world.step(1 / 60)
        thawed.step(1 / 60)
    assert world.state.body.tobytes() == thawed.state.body.tobytes()
    assert world.contacts().impulse.tobytes() == thawed.contacts().impulse.tobytes()


def _play(env: Any, moves: np.ndarray) -> list[Any]:
    return [list(env.step(a)) for a in moves]


@pytest.mark.parametrize(("env_id", "kwargs"), CASES, ids=["pool-1", "pool-15", "slingshot"])
def test_a_restored_single_env_replays_the_same_shots(env_id, kwargs):
    """save_state, play, restore_state, play the same shots again: bitwise the same
    observations, rewards, flags and infos, through episode ends (the unwrapped env has
    no step cap; resets draw from the restored generator)."""
    env = gym.make(env_id, **kwargs).unwrapped
    env.reset(seed=2)
    rng = np.random.default_rng(5)
    env.step(rng.uniform(-1, 1, 2).astype(np.float32))
    saved, start = env.save_state(), env.game.observe()[0].copy()
    moves = rng.uniform(-1, 1, (5, 2)).astype(np.float32)
    first = _play(env, moves)
    assert env.restore_state(saved).tobytes() == start.tobytes()
    assert same_bitwise(_play(env, moves), first)
    assert env.restore_state(saved).tobytes() == start.tobytes()  # a state is reusable


@pytest.mark.parametrize(("env_id", "kwargs"), CASES, ids=["pool-1", "pool-15", "slingshot"])
def test_a_vector_env_restores_chosen_worlds_and_leaves_the_others(env_id, kwargs):
    """Restored into world 1 only, world 1 replays its saved future bitwise while worlds
    0 and 2 play on from where they were (their own next shots, also bitwise what a
    copy of the env made before the restore plays)."""
    venv = gym.make_vec(env_id, 3, vectorization_mode="vector_entry_point",
                        max_episode_steps=3, **kwargs)  # fmt: skip
    venv.reset(seed=8)
    rng = np.random.default_rng(6)
    saved = venv.save_state()
    moves = rng.uniform(-1, 1, (4, 3, 2)).astype(np.float32)
    first = _play(venv, moves)
    twin = copy.deepcopy(venv)
    venv.restore_state(saved, worlds=[1])
    later = rng.uniform(-1, 1, (4, 3, 2)).astype(np.float32)
    mixed = later.copy()
    mixed[:, 1] = moves[:, 1]  # world 1 replays its first moves
    got, others = _play(venv, mixed), _play(twin, mixed)
    for t in range(4):
        for k in range(4):  # observations, rewards, terminated, truncated
            assert np.asarray(got[t][k])[1].tobytes() == np.asarray(first[t][k])[1].tobytes()
            for w in (0, 2):
                assert np.asarray(got[t][k])[w].tobytes() == np.asarray(others[t][k])[w].tobytes()


def test_a_state_from_another_env_is_refused():
    one = gym.make_vec("Pool2D-v0", 2, vectorization_mode="vector_entry_point", num_balls=1)
    three = gym.make_vec("Pool2D-v0", 3, vectorization_mode="vector_entry_point", num_balls=1)
    one.reset(seed=0)
    three.reset(seed=0)
    with pytest.raises(ValueError, match="2 worlds"):
        three.restore_state(one.save_state())
    with pytest.raises(ValueError, match="worlds must be indices"):
        three.restore_state(three.save_state(), worlds=[5])
    with pytest.raises(ValueError, match="state must be"):
        three.restore_state("a state")
