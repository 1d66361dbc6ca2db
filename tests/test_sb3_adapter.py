"""The SB3 ``VecEnv`` adapter over the batched Pool2D vector env (``impulse2d.envs.sb3``).

Shots are cut at 2-3 simulated seconds and episodes at 3 shots, so that every test plays
only a few fast steps and still sees episodes end.
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.vector import AutoresetMode
from stable_baselines3 import PPO
from stable_baselines3.common.evaluation import evaluate_policy
from stable_baselines3.common.monitor import Monitor
from stable_baselines3.common.vec_env import DummyVecEnv, VecMonitor

from bitwise import same_bitwise
from impulse2d.envs.sb3 import SB3VecEnv, _env_info, make_sb3_vec_env

N = 4
FAST = {"num_balls": 1, "max_episode_steps": 3, "max_shot_seconds": 3.0}


def batched(num_envs: int = N, **kwargs: Any) -> SB3VecEnv:
    options = {**FAST, **kwargs}
    return SB3VecEnv(
        gym.make_vec(
            "Pool2D-v0", num_envs=num_envs, vectorization_mode="vector_entry_point", **options
        )
    )


def actions(steps: int, num_envs: int = N) -> np.ndarray:
    return np.random.default_rng(1).uniform(-1, 1, (steps, num_envs, 2)).astype(np.float32)


@pytest.fixture(scope="module")
def both() -> dict[str, list[Any]]:
    """The adapter and SB3's DummyVecEnv over single envs, seeded 7, same actions."""
    runs: dict[str, list[Any]] = {}
    dummy = DummyVecEnv([lambda: gym.make("Pool2D-v0", **FAST) for _ in range(N)])
    for name, venv in (("adapter", batched()), ("dummy", dummy)):
        assert venv.seed(7) == [7, 8, 9, 10]
        record: list[Any] = [(venv.reset(), None, None, [{}] * N)]
        record += [venv.step(a) for a in actions(6)]
        runs[name] = record
        venv.close()
    return runs


def test_matches_dummy_vec_env_bitwise(both: dict[str, list[Any]]) -> None:
    truncations = 0
    for (obs, rew, done, infos), (obs_d, rew_d, done_d, infos_d) in zip(
        both["adapter"], both["dummy"], strict=True
    ):
        assert obs.dtype == obs_d.dtype and obs.tobytes() == obs_d.tobytes()
        if rew is not None:
            assert rew.dtype == rew_d.dtype == np.float32 and rew.tobytes() == rew_d.tobytes()
            assert done.dtype == done_d.dtype == bool and np.array_equal(done, done_d)
        for info, info_d in zip(infos, infos_d, strict=True):
            keys = set(info) - {"terminal_observation"}
            assert keys == set(info_d) - {"terminal_observation"}
            assert {k: info[k] for k in keys} == {k: info_d[k] for k in keys}
            assert ("terminal_observation" in info) == ("terminal_observation" in info_d)
            truncations += bool(info.get("TimeLimit.truncated"))
    assert truncations > 0  # the time limit was met and reported


def test_terminal_observation_matches_dummy_vec_env(both: dict[str, list[Any]]) -> None:
    ended = 0
    for (*_, infos), (*_, infos_d) in zip(both["adapter"], both["dummy"], strict=True):
        for info, info_d in zip(infos, infos_d, strict=True):
            if "terminal_observation" in info_d:
                ended += 1
                term, term_d = info["terminal_observation"], info_d["terminal_observation"]
                assert term.dtype == term_d.dtype and term.tobytes() == term_d.tobytes()
    assert ended > 0


def test_seed_then_reset_is_deterministic() -> None:
    venv = batched()
    assert venv.seed(3) == [3, 4, 5, 6]
    first = venv.reset()
    assert venv._seeds == [None] * N  # a seed is used by one reset only
    steps = [venv.step(a)[0] for a in actions(2)]
    assert not np.array_equal(venv.reset(), first)  # unseeded: the generators go on
    venv.seed(3)
    assert venv.reset().tobytes() == first.tobytes()
    for a, obs in zip(actions(2), steps, strict=True):
        assert venv.step(a)[0].tobytes() == obs.tobytes()
    fresh = make_sb3_vec_env("Pool2D-v0", N, seed=3, **FAST)
    assert fresh.reset().tobytes() == first.tobytes()
    assert not np.array_equal(first[0], first[1])  # env i is seeded 3 + i


def test_spaces_reset_infos_and_options() -> None:
    venv = batched()
    assert venv.num_envs == N
    assert venv.observation_space == venv.venv.single_observation_space
    assert venv.action_space == venv.venv.single_action_space
    obs = venv.reset()
    assert obs.shape == (N, *venv.observation_space.shape) and obs.dtype == np.float32
    assert venv.reset_infos == [{}] * N
    venv.set_options({"anything": 1})  # one dict for all: passed to the vector env's reset
    venv.reset()
    venv.set_options([{"a": 1}, {}, {}, {}])
    with pytest.raises(ValueError, match="one options dict"):
        venv.reset()
    venv.step_async(actions(1)[0])
    venv.step_wait()
    with pytest.raises(RuntimeError, match="step_async"):
        venv.step_wait()


def test_attributes_methods_and_wrappers() -> None:
    venv = batched()
    assert venv.get_attr("render_mode") == [None] * N
    games = venv.get_attr("game", indices=[1, 3])
    assert len(games) == 2 and games[0] is games[1] is venv.venv.game
    assert venv.get_attr("num_envs", indices=2) == [N]
    assert venv.has_attr("game") and not venv.has_attr("no_such_attribute")
    with pytest.raises(AttributeError):
        venv.get_attr("no_such_attribute")
    venv.set_attr("max_episode_steps", 5)
    assert venv.get_attr("max_episode_steps") == [5] * N
    with pytest.raises(ValueError, match="indices"):
        venv.set_attr("max_episode_steps", 2, indices=[0])
    results = venv.env_method("reset", seed=1, indices=[0, 2])
    assert len(results) == 2 and results[0] is results[1]
    assert results[0][0].shape == (N, *venv.observation_space.shape)
    assert venv.env_is_wrapped(Monitor) == [False] * N
    assert venv.env_is_wrapped(Monitor, indices=2) == [False]


def _record(venv: SB3VecEnv, steps: int = 6) -> list[Any]:
    venv.seed(7)
    record: list[Any] = [venv.reset()]
    for a in actions(steps):
        obs, rew, done, infos = venv.step(a)
        finals = [info.get("terminal_observation") for info in infos]
        record.append((obs, rew, done, finals, [i["TimeLimit.truncated"] for i in infos]))
    venv.close()
    return record


@pytest.mark.parametrize("mode", list(AutoresetMode))
def test_every_autoreset_mode_gives_sb3_the_same_episodes(mode: AutoresetMode) -> None:
    """SB3 sees the same-step convention whatever the vector env does: the batched env
    and Gymnasium's SyncVectorEnv of single envs, each in any of the three modes
    (finished envs reset through ``reset_mask``), give bitwise the same observations,
    rewards, dones and terminal observations."""
    reference = _record(batched(autoreset_mode=AutoresetMode.SAME_STEP))
    assert any(done.any() for _, _, done, _, _ in reference[1:])  # episodes do end
    sync = gym.make_vec(
        "Pool2D-v0", num_envs=N, vectorization_mode="sync",
        vector_kwargs={"autoreset_mode": mode}, **FAST,
    )  # fmt: skip
    assert same_bitwise(_record(SB3VecEnv(sync)), reference)
    assert same_bitwise(_record(batched(autoreset_mode=mode)), reference)


def test_make_sb3_vec_env_asks_for_same_step() -> None:
    venv = make_sb3_vec_env("Pool2D-v0", N, seed=0, **FAST)
    assert venv.venv.autoreset_mode is AutoresetMode.SAME_STEP and venv.same_step
    venv.close()


def test_render_and_get_images() -> None:
    venv = batched(render_mode="rgb_array")
    assert venv.render_mode == "rgb_array"
    venv.reset()
    frames = venv.get_images()
    assert len(frames) == N
    for frame in frames:
        assert frame.shape == (270, 480, 3) and frame.dtype == np.uint8
    assert venv.render().shape == (2 * 270, 2 * 480, 3)  # SB3 tiles the frames 2 x 2
    plain = batched()
    with pytest.warns(UserWarning, match="rgb_array"):
        assert plain.get_images() == [None] * N


def test_env_info_reads_the_vector_layout() -> None:
    info = {
        "a": np.array([1, 2]),
        "_a": np.array([True, False]),
        "_private": np.array([3.5, 4.5]),
        "__private": np.array([False, True]),
        "nested": {"b": np.array([True, True]), "_b": np.array([False, True])},
        "_nested": np.array([False, True]),
        "unmasked": np.array([5, 6]),
    }
    assert _env_info(info, 0) == {"a": 1}
    assert _env_info(info, 1) == {"_private": 4.5, "nested": {"b": True}}
    assert type(_env_info(info, 0)["a"]) is int


def test_ppo_learns_with_vec_monitor_and_evaluates() -> None:
    venv = make_sb3_vec_env("Pool2D-v0", 8, seed=0, **{**FAST, "max_shot_seconds": 2.0})
    monitored = VecMonitor(venv)
    model = PPO("MlpPolicy", monitored, n_steps=16, batch_size=32, n_epochs=2, seed=0, device="cpu")
    model.learn(total_timesteps=256)
    assert model.num_timesteps == 256
    episodes = list(model.ep_info_buffer)
    assert len(episodes) >= 8
    assert all(1 <= e["l"] <= 3 and np.isfinite(e["r"]) for e in episodes)
    mean, std = evaluate_policy(model, monitored, n_eval_episodes=8, warn=False)
    assert np.isfinite(mean) and np.isfinite(std)
    monitored.close()
