"""Threads and processes: a batch steps bitwise the same on one thread or several, and in
child processes started by fork (after the parent ran threads), spawn or forkserver, as
SB3's SubprocVecEnv and Gymnasium's AsyncVectorEnv start them."""

from __future__ import annotations

import hashlib
import multiprocessing
import subprocess
import sys
import threading

import gymnasium as gym
import numpy as np
import pytest
from stable_baselines3.common.vec_env import DummyVecEnv, SubprocVecEnv

import impulse2d as p2
from impulse2d.core.runner import available_threads

DT = 1 / 120


def _pool_batch(threads: int | None = None) -> p2.World:
    """Eight pool breaks, each world's cue ball a different shot."""
    world = p2.World(gravity=(0.0, 0.0), substeps=2, restitution_mixing="min")
    for sign in (-1.0, 1.0):
        world.add(p2.Box(position=(0.0, sign * 0.7), width=2.6, height=0.1, fixed=True))
        world.add(p2.Box(position=(sign * 1.3, 0.0), width=0.1, height=1.4, fixed=True))
    rack = [(0.5 + 0.05 * row, 0.0575 * (k - row / 2)) for row in range(5) for k in range(row + 1)]
    for x, y in rack:
        world.add(p2.Circle(position=(x, y), radius=0.0285, mass=0.17, restitution=0.95))
    cue = world.add(p2.Circle(position=(-0.6, 0.0), radius=0.0285, mass=0.17, restitution=0.95))
    batch = world.replicate(8)
    if threads is not None:
        batch.threads = threads
    angles = np.linspace(-0.05, 0.05, 8)
    batch.bodies[cue.slot].velocity = 6.0 * np.stack([np.cos(angles), np.sin(angles)], axis=1)
    return batch


def _fingerprint(threads: int | None = None, steps: int = 150) -> str:
    """A hash of the whole state of ``_pool_batch`` after ``steps`` steps."""
    batch = _pool_batch(threads)
    for _ in range(steps):
        batch.step(DT)
    batch.run_until_rest(DT, 200)
    digest = hashlib.sha256()
    for array in batch.state.arrays().values():
        digest.update(np.ascontiguousarray(array).tobytes())
    return digest.hexdigest()


def _child(queue: multiprocessing.Queue) -> None:
    fingerprint = _fingerprint()
    helpers = [t for t in threading.enumerate() if t.name.startswith("impulse2d")]
    queue.put((fingerprint, len(helpers)))


@pytest.mark.skipif(available_threads() < 2, reason="needs two cores")
def test_any_thread_count_gives_the_same_state():
    assert _fingerprint(threads=1) == _fingerprint(threads=2)


def test_threads_setting_is_checked():
    for bad in (0, -1, 1.5, True, "2", available_threads() + 1):
        with pytest.raises(ValueError, match="threads"):
            p2.World(threads=bad)
    world = p2.World()
    with pytest.raises(ValueError, match="threads"):
        world.threads = 0
    world.threads = 1
    assert world.threads == 1


@pytest.mark.parametrize("method", ["fork", "spawn", "forkserver"])
def test_child_processes_step_like_the_parent(method):
    """The parent has run its helper threads before the fork; every child, forked or
    not, steps its batches on threads of its own (a forked child has none of the
    parent's: it starts new ones) and gives the parent's state bitwise."""
    expected = _fingerprint()  # threads started here, before any fork
    context = multiprocessing.get_context(method)
    queue = context.Queue()
    process = context.Process(target=_child, args=(queue,))
    process.start()
    got = queue.get(timeout=300)
    process.join(timeout=60)
    assert process.exitcode == 0
    fingerprint, helpers = got
    assert fingerprint == expected
    assert helpers == (1 if available_threads() >= 2 else 0)


def _pool_env() -> gym.Env:
    return gym.make("impulse2d:Pool2D-v0", num_balls=1)


def _play(venv, steps: int = 6) -> np.ndarray:
    venv.seed(7)
    observations = [venv.reset()]
    rng = np.random.default_rng(0)
    for _ in range(steps):
        actions = rng.uniform(-1, 1, (venv.num_envs, 2)).astype(np.float32)
        observations.append(venv.step(actions)[0])
    venv.close()
    return np.array(observations)


@pytest.mark.parametrize("method", ["fork", "spawn"])
def test_sb3_subproc_vec_env_matches_dummy_vec_env(method):
    """SB3's SubprocVecEnv workers (forked after the parent ran threads, or spawned) play
    the same shots as DummyVecEnv in this process, bitwise."""
    _fingerprint(steps=5)  # make sure this process has run threads before forking
    reference = _play(DummyVecEnv([_pool_env, _pool_env]))
    got = _play(SubprocVecEnv([_pool_env, _pool_env], start_method=method))
    np.testing.assert_array_equal(got, reference)


@pytest.mark.parametrize("context", ["fork", "spawn"])
def test_gymnasium_async_vector_env_matches_sync(context):
    """Gymnasium's AsyncVectorEnv (fork is its default on Linux) gives SyncVectorEnv's
    observations bitwise."""
    _fingerprint(steps=5)
    fns = [_pool_env, _pool_env]

    def play(venv: gym.vector.VectorEnv) -> np.ndarray:
        observations = [venv.reset(seed=3)[0]]
        rng = np.random.default_rng(1)
        for _ in range(4):
            observations.append(venv.step(rng.uniform(-1, 1, (2, 2)).astype(np.float32))[0])
        venv.close()
        return np.array(observations)

    reference = play(gym.vector.SyncVectorEnv(fns))
    got = play(gym.vector.AsyncVectorEnv(fns, context=context))
    np.testing.assert_array_equal(got, reference)


def _run_python(code: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=600
    )  # fmt: skip


_SUBPROC = (
    "from stable_baselines3.common.env_util import make_vec_env\n"
    "from stable_baselines3.common.vec_env import SubprocVecEnv\n"
    "v = make_vec_env({id!r}, n_envs=2, vec_env_cls=SubprocVecEnv, env_kwargs={{'num_balls': 1}})\n"
    "print('observations', v.reset().shape)\n"
    "v.close()\n"
)


def test_workers_that_never_imported_impulse2d_take_the_module_qualified_id():
    """What docs/envs/index.md tells users of ``SubprocVecEnv`` from ``python -c`` or a notebook:
    its forkserver workers never import impulse2d, so the plain id is unknown there, and
    ``impulse2d:Pool2D-v0`` works."""
    plain = _run_python(_SUBPROC.format(id="Pool2D-v0"))
    assert plain.returncode != 0 and "Pool2D" in plain.stderr and "exist" in plain.stderr
    qualified = _run_python(_SUBPROC.format(id="impulse2d:Pool2D-v0"))
    assert qualified.returncode == 0, qualified.stderr
    assert "observations (2, " in qualified.stdout
