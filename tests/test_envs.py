"""The Gymnasium contract of Pool2D-v0, Slingshot2D-v0 and Slingshot2DBlocks-v0: checkers,
registration, determinism, vector env = single envs, bad actions, rendering and the
scripted baselines.

Pool tests use one object ball at random spots (short shots); slingshot tests the
hand-made levels. The rules and physics of each game are in ``test_pool_rules.py`` and
``test_slingshot_rules.py``.
"""

from __future__ import annotations

import itertools
import logging
import subprocess
import sys
import warnings
from typing import Any

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env as gym_check_env
from gymnasium.vector import AutoresetMode
from stable_baselines3.common.env_checker import check_env as sb3_check_env

import impulse2d  # noqa: F401  (registers the ids)
from impulse2d.envs import VARIANTS
from impulse2d.envs.baselines import pool_ghost_ball, slingshot_ballistic

OPTIONS: dict[str, dict[str, Any]] = {
    "Pool2D-v0": {"num_balls": 1},
    "Slingshot2D-v0": {"level": "handmade"},
    "Slingshot2DBlocks-v0": {"level": "handmade"},
}
IDS = list(OPTIONS)


def make(env_id: str, **kwargs: Any) -> gym.Env:
    return gym.make(env_id, **{**OPTIONS[env_id], **kwargs})


def make_vec(env_id: str, num_envs: int, **kwargs: Any) -> gym.vector.VectorEnv:
    return gym.make_vec(
        env_id,
        num_envs=num_envs,
        vectorization_mode="vector_entry_point",
        **{**OPTIONS[env_id], **kwargs},
    )


def actions(count: int, seed: int = 0, shape: tuple[int, ...] = (2,)) -> np.ndarray:
    return np.random.default_rng(seed).uniform(-1, 1, (count, *shape)).astype(np.float32)


@pytest.mark.parametrize("env_id", IDS)
def test_gymnasium_and_sb3_checkers_pass_without_warnings(env_id: str) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        gym_check_env(make(env_id).unwrapped, skip_render_check=True)
        sb3_check_env(make(env_id).unwrapped, warn=True)
        # Through gym.make's wrappers (the passive checker, the time limit) too.
        env = make(env_id)
        obs, info = env.reset(seed=0)
        assert env.observation_space.contains(obs) and info == {}
        for action in actions(3):
            obs, reward, terminated, truncated, info = env.step(action)
            assert env.observation_space.contains(obs)
            assert type(reward) is float and type(terminated) is bool
            if terminated or truncated:
                obs, _ = env.reset()


@pytest.mark.parametrize("env_id", IDS)
def test_registered_in_a_fresh_process_without_import(env_id: str) -> None:
    code = (
        "import gymnasium as gym\n"
        f"env = gym.make('impulse2d:{env_id}')\n"
        "obs, _ = env.reset(seed=1)\n"
        "print(env.spec.max_episode_steps, obs.shape, obs.dtype)\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=120
    ).stdout.split()
    env = gym.make(env_id)
    assert out == [
        str(env.spec.max_episode_steps),
        str(env.observation_space.shape).replace(" ", ""),
        "float32",
    ]


@pytest.mark.parametrize("env_id", IDS)
def test_same_seed_and_actions_give_bitwise_the_same_episode(env_id: str) -> None:
    def play() -> list[bytes]:
        env = make(env_id)
        record = [env.reset(seed=5)[0].tobytes()]
        for action in actions(4, seed=3):
            obs, reward, terminated, truncated, info = env.step(action)
            record += [obs.tobytes(), np.float64(reward).tobytes(), repr(sorted(info.items()))]
            if terminated or truncated:
                record.append(env.reset()[0].tobytes())
        return record

    assert play() == play()


@pytest.mark.parametrize("defaults", [False, True], ids=["learnable", "defaults"])
@pytest.mark.parametrize("env_id", IDS)
def test_vector_env_i_equals_a_single_env_seeded_seed_plus_i(env_id: str, defaults: bool) -> None:
    """Bitwise, through terminations and the vector env's same-step autoreset; for the
    learnable variants and for the defaults (the 15-ball rack, random levels)."""
    n, steps, seed = 4, 5, 11
    moves = actions(steps, seed=2, shape=(n, 2))
    options = {} if defaults else OPTIONS[env_id]
    venv = gym.make_vec(
        env_id, n, vectorization_mode="vector_entry_point", max_episode_steps=3,
        autoreset_mode=gym.vector.AutoresetMode.SAME_STEP, **options,
    )  # fmt: skip
    assert venv.autoreset_mode == venv.metadata["autoreset_mode"] == AutoresetMode.SAME_STEP
    vector = [venv.reset(seed=seed)[0]]
    vector_final: dict[tuple[int, int], np.ndarray] = {}
    vector_rewards = []
    for t in range(steps):
        obs, reward, terminated, truncated, info = venv.step(moves[t])
        vector.append(obs)
        vector_rewards.append(reward)
        for i in np.flatnonzero(terminated | truncated):
            vector_final[(t, i)] = info["final_obs"][i]
    for i in range(n):
        env = gym.make(env_id, max_episode_steps=3, **options)
        obs, _ = env.reset(seed=seed + i)
        assert obs.tobytes() == vector[0][i].tobytes()
        for t in range(steps):
            obs, reward, terminated, truncated, _ = env.step(moves[t, i])
            assert reward == vector_rewards[t][i]
            if terminated or truncated:
                assert obs.tobytes() == vector_final[(t, i)].tobytes()
                obs, _ = env.reset()
            else:
                assert (t, i) not in vector_final
            assert obs.tobytes() == vector[t + 1][i].tobytes()


@pytest.mark.parametrize("env_id", IDS)
def test_next_step_autoreset_is_gymnasiums_sync_vector_env_bitwise(env_id: str) -> None:
    """The default, NEXT_STEP: every return of every step is what Gymnasium's own
    SyncVectorEnv over single envs gives in that mode (the step after an episode ends
    resets the env, ignores its action, reward 0), bitwise; ``reset_mask`` resets only
    the chosen envs, as there."""
    n, steps, seed = 4, 6, 5
    moves = actions(steps, seed=3, shape=(n, 2))
    native = gym.make_vec(env_id, n, vectorization_mode="vector_entry_point",
                          max_episode_steps=2, **OPTIONS[env_id])  # fmt: skip
    sync = gym.make_vec(env_id, n, vectorization_mode="sync", max_episode_steps=2,
                        vector_kwargs={"autoreset_mode": AutoresetMode.NEXT_STEP},
                        **OPTIONS[env_id])  # fmt: skip
    assert native.autoreset_mode is native.metadata["autoreset_mode"] is AutoresetMode.NEXT_STEP
    first, second = native.reset(seed=seed)[0], sync.reset(seed=seed)[0]
    assert first.tobytes() == second.tobytes()
    ended = 0
    for t in range(steps):
        mine, theirs = native.step(moves[t]), sync.step(moves[t])
        for a, b in zip(mine[:4], theirs[:4], strict=True):
            assert np.asarray(a).tobytes() == np.asarray(b).astype(np.asarray(a).dtype).tobytes()
        ended += int((mine[2] | mine[3]).sum())
    assert ended >= n  # every env went through an autoreset
    mask = np.array([True, False, False, True])
    mine, theirs = (
        native.reset(options={"reset_mask": mask}),
        sync.reset(options={"reset_mask": mask.copy()}),
    )
    assert mine[0].tobytes() == theirs[0].tobytes()


def test_gymnasiums_vector_wrappers_work_on_the_vector_env() -> None:
    """What CleanRL-style scripts put on it: ``FlattenObservation`` and
    ``NormalizeObservation`` (which need NEXT_STEP or DISABLED autoreset) and
    ``RecordEpisodeStatistics``, through episodes that end."""
    from gymnasium.wrappers import vector as vw

    venv = gym.make_vec("Pool2D-v0", 3, vectorization_mode="vector_entry_point",
                        max_episode_steps=2, **OPTIONS["Pool2D-v0"])  # fmt: skip
    venv = vw.RecordEpisodeStatistics(vw.NormalizeObservation(vw.FlattenObservation(venv)))
    obs, _ = venv.reset(seed=0)
    episodes = 0
    for t in range(5):
        obs, _, _, _, info = venv.step(actions(1, seed=t, shape=(3, 2))[0])
        assert obs.shape == (3, *venv.single_observation_space.shape) and np.isfinite(obs).all()
        if "episode" in info:
            episodes += int(info["_episode"].sum())
            assert (info["episode"]["l"][info["_episode"]] == 2).all()  # the step cap
    assert episodes >= 3
    venv.close()


@pytest.mark.parametrize("variant", ["Pool2DOneBall-v0", "Slingshot2DHandmade-v0"])
def test_a_learnable_variant_is_its_base_game_with_the_task_s_arguments(variant) -> None:
    """For tools that take only an id: each registered variant plays bitwise as the base
    id made with the variant's keyword arguments and episode length, single and batched,
    and passes Gymnasium's checker."""
    base, kwargs, max_steps = VARIANTS[variant]
    moves = actions(max_steps + 1, seed=4, shape=(2, 2))
    for vector in (False, True):
        if vector:
            mine = gym.make_vec(variant, 2, vectorization_mode="vector_entry_point")
            theirs = gym.make_vec(base, 2, vectorization_mode="vector_entry_point",
                                  max_episode_steps=max_steps, **kwargs)  # fmt: skip
        else:
            mine, theirs = gym.make(variant), gym.make(base, max_episode_steps=max_steps, **kwargs)
        assert mine.reset(seed=6)[0].tobytes() == theirs.reset(seed=6)[0].tobytes()
        ended = False
        for t in range(max_steps + 1):
            action = moves[t] if vector else moves[t, 0]
            a, b = mine.step(action), theirs.step(action)
            assert all(
                np.asarray(x).tobytes() == np.asarray(y).tobytes()
                for x, y in zip(a[:4], b[:4], strict=True)
            )
            ended |= bool(np.any(a[2]) or np.any(a[3]))
        assert ended  # within the variant's episode length
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        gym_check_env(gym.make(variant).unwrapped, skip_render_check=True)
        sb3_check_env(gym.make(variant).unwrapped, warn=True)


def test_vector_env_autoreset_mode_is_checked() -> None:
    with pytest.raises(ValueError, match="autoreset_mode must be"):
        gym.make_vec("Pool2D-v0", 2, vectorization_mode="vector_entry_point",
                     autoreset_mode="sometimes")  # fmt: skip


@pytest.mark.parametrize(
    "mask", [np.array([True, False]), np.array([1, 0, 1]), np.zeros(3, bool), [True] * 3]
)
def test_a_bad_reset_mask_is_refused_by_name(mask) -> None:
    venv = gym.make_vec("Pool2D-v0", 3, vectorization_mode="vector_entry_point", num_balls=1)
    venv.reset(seed=0)
    with pytest.raises(ValueError, match="reset_mask"):
        venv.reset(options={"reset_mask": mask})


def test_disabled_autoreset_is_gymnasiums_and_asks_for_resets() -> None:
    """DISABLED: nothing resets by itself (bitwise Gymnasium's SyncVectorEnv in that mode,
    with the finished envs reset through ``reset_mask``), and stepping an env whose
    episode ended without resetting it is refused with what to do."""
    n, seed = 3, 2
    moves = actions(6, seed=1, shape=(n, 2))
    made = {
        "native": gym.make_vec("Pool2D-v0", n, vectorization_mode="vector_entry_point",
                               max_episode_steps=2, autoreset_mode=AutoresetMode.DISABLED,
                               **OPTIONS["Pool2D-v0"]),
        "sync": gym.make_vec("Pool2D-v0", n, vectorization_mode="sync", max_episode_steps=2,
                             vector_kwargs={"autoreset_mode": AutoresetMode.DISABLED},
                             **OPTIONS["Pool2D-v0"]),
    }  # fmt: skip
    runs = {}
    for name, venv in made.items():
        record = [venv.reset(seed=seed)[0]]
        for t in range(6):
            obs, reward, terminated, truncated, _ = venv.step(moves[t])
            record += [obs, reward.astype(np.float64), terminated, truncated]
            done = terminated | truncated
            if done.any():
                record.append(venv.reset(options={"reset_mask": done})[0])
        runs[name] = record
    assert len(runs["native"]) == len(runs["sync"]) > 25  # resets happened
    for a, b in zip(runs["native"], runs["sync"], strict=True):
        assert np.asarray(a).tobytes() == np.asarray(b).tobytes()
    venv = made["native"]
    venv.reset(seed=0)
    venv.step(moves[0])
    venv.step(moves[1])  # the step cap: every episode has ended
    with pytest.raises(RuntimeError, match="reset_mask"):
        venv.step(moves[2])


@pytest.mark.parametrize("env_id", IDS)
def test_bad_actions_raise_and_out_of_range_actions_are_clipped(env_id: str) -> None:
    env = make(env_id).unwrapped
    env.reset(seed=0)
    for bad in ([np.nan, 0.0], [0.0, np.inf], [0.0, -np.inf]):
        with pytest.raises(ValueError, match="action must be finite"):
            env.step(np.array(bad, np.float32))
    with pytest.raises(ValueError, match="action must have shape"):
        env.step(np.zeros(3, np.float32))
    with pytest.raises(ValueError, match="action must be"):
        env.step("left")
    # numpy would drop the imaginary part, and turn True into 1.0, without a word.
    for bad in (np.array([0.5 + 0.0j, 0.1]), np.array([0.5, 0.1 + 1j]), [True, False], None):
        with pytest.raises(ValueError, match="action must be"):
            env.step(bad)
    vector = make_vec(env_id, 2)
    vector.reset(seed=0)
    with pytest.raises(ValueError, match="action must be real"):
        vector.step(np.full((2, 2), 0.5 + 0.0j))
    big = make(env_id)
    big.reset(seed=4)
    clipped = make(env_id)
    clipped.reset(seed=4)
    out_big = big.step(np.array([0.3, 7.0], np.float32))
    out_clipped = clipped.step(np.array([0.3, 1.0], np.float32))
    assert out_big[0].tobytes() == out_clipped[0].tobytes() and out_big[1] == out_clipped[1]


def test_step_before_reset_and_bad_options_are_refused() -> None:
    with pytest.raises(RuntimeError, match="reset"):
        gym.make("Pool2D-v0").unwrapped.step(np.zeros(2, np.float32))
    with pytest.raises(ValueError, match="num_balls must be in"):
        gym.make("Pool2D-v0", num_balls=0)
    with pytest.raises(ValueError, match="layout"):
        gym.make("Pool2D-v0", layout="diamond")
    with pytest.raises(ValueError, match="level"):
        gym.make("Slingshot2D-v0", level="moon")
    with pytest.raises(ValueError, match="num_birds"):
        gym.make("Slingshot2D-v0", num_birds=0)
    with pytest.raises(ValueError, match="render_mode"), warnings.catch_warnings():
        warnings.simplefilter("ignore")  # gym.make warns first, then the env refuses
        gym.make("Pool2D-v0", render_mode="ascii")
    with pytest.raises(ValueError, match="num_envs"):
        gym.make_vec("Pool2D-v0", num_envs=0, vectorization_mode="vector_entry_point")
    # Every keyword and kind of wrong value: tests/test_env_arguments.py.


@pytest.mark.parametrize("env_id", IDS)
def test_rgb_array_is_the_frame_after_the_shot(env_id: str) -> None:
    env = make(env_id, render_mode="rgb_array")
    env.reset(seed=0)
    before = env.render()
    env.step(np.array([0.1, 0.5], np.float32))
    after = env.render()
    assert before.shape == after.shape == (270, 480, 3) and after.dtype == np.uint8
    assert not np.array_equal(before, after)  # something moved or disappeared


@pytest.mark.parametrize("env_id", IDS)
def test_rgb_array_list_holds_the_frames_during_the_shot(env_id: str) -> None:
    env = make(env_id, render_mode="rgb_array_list")
    env.reset(seed=0)
    assert len(env.render()) == 1  # the starting frame
    _, _, _, _, info = env.step(np.array([0.1, 0.5], np.float32))
    frames = env.render()
    dt = env.unwrapped.game.dt
    # One frame per 1/30 s of simulated time during the shot, and the one after it.
    expected = info["physics_steps"] // round(1 / (30 * dt)) + 1
    assert abs(len(frames) - expected) <= 1 and len(frames) >= 3
    changes = [not np.array_equal(a, b) for a, b in itertools.pairwise(frames)]
    assert sum(changes) >= 2  # the picture moves during the shot
    assert env.render() == []  # handed over once


def _no_display(monkeypatch: pytest.MonkeyPatch) -> None:
    for name in ("DISPLAY", "WAYLAND_DISPLAY", "SDL_VIDEODRIVER"):
        monkeypatch.delenv(name, raising=False)


@pytest.mark.parametrize("env_id", [*IDS, *VARIANTS])
def test_checkers_pass_in_every_render_mode_without_a_display(env_id, monkeypatch) -> None:
    """Gymnasium's checker with its render checks (it makes the env again in every mode
    of ``metadata``, ``human`` included, resets it and renders), on a machine with no
    display, warnings as errors: as it passes for Gymnasium's own envs. SB3's too."""
    _no_display(monkeypatch)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        gym_check_env(gym.make(env_id).unwrapped)
        sb3_check_env(gym.make(env_id).unwrapped, warn=True)


@pytest.mark.parametrize("env_id", IDS)
def test_human_render_without_a_display_says_so_at_the_first_frame(
    env_id, monkeypatch, caplog
) -> None:
    """No display server: making the env works (Gymnasium's checker makes every mode);
    at the first frame (the reset) the env says once, as a logged warning, what is
    missing and what to do (the display variables, xvfb-run, ``rgb_array``), then plays
    on without a window: no frames drawn, nothing raised, no Python warning."""
    _no_display(monkeypatch)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        env = make(env_id, render_mode="human")
        assert not caplog.records  # nothing said before a frame is due
        with caplog.at_level(logging.WARNING, logger="impulse2d.envs"):
            env.reset(seed=0)
            for action in actions(2):
                *_, terminated, truncated, _ = env.step(action)
                if terminated or truncated:
                    env.reset()
            assert env.render() is None
            env.reset()
    told = [r for r in caplog.records if r.name == "impulse2d.envs"]
    assert len(told) == 1 and told[0].levelno == logging.WARNING
    message = told[0].getMessage()
    for words in ("needs a display", "DISPLAY=None", "xvfb-run", "render_mode='rgb_array'"):
        assert words in message
    frames = env.unwrapped._frames
    assert frames.window is None and frames.every == 0  # no frames during the shots
    env.close()


def test_human_render_with_a_headless_driver_asked_for_plays(monkeypatch, caplog) -> None:
    """``SDL_VIDEODRIVER=dummy`` is the user's own choice (tests, recording): the window
    opens (into memory) and shows the frames of the shot, and nothing is said."""
    monkeypatch.setenv("SDL_VIDEODRIVER", "dummy")
    env = make("Pool2D-v0", render_mode="human")
    with caplog.at_level(logging.WARNING, logger="impulse2d.envs"):
        env.reset(seed=0)
        _, _, _, _, info = env.step(np.array([0.1, -1.0], np.float32))  # the softest shot
    assert info["physics_steps"] > 0 and not caplog.records
    frames = env.unwrapped._frames
    assert frames.window is not None and frames.every == round(1 / (30 * env.unwrapped.game.dt))
    env.close()


def test_vector_env_renders_one_frame_per_world() -> None:
    venv = make_vec("Pool2D-v0", 3, render_mode="rgb_array")
    venv.reset(seed=0)
    frames = venv.render()
    assert len(frames) == 3 and all(f.shape == (270, 480, 3) for f in frames)
    assert not np.array_equal(frames[0], frames[1])  # different random layouts


def test_list_of_seeds_seeds_each_vector_env() -> None:
    venv = make_vec("Pool2D-v0", 2)
    obs, _ = venv.reset(seed=[7, 3])
    for i, seed in enumerate((7, 3)):
        single, _ = make("Pool2D-v0").reset(seed=seed)
        assert single.tobytes() == obs[i].tobytes()


def _mean_return(env_id: str, policy: Any, episodes: int, seed: int, **options: Any) -> float:
    """Mean return of the first episode of each of ``episodes`` vector envs."""
    venv = make_vec(env_id, episodes, **options)
    obs, _ = venv.reset(seed=seed)
    rng = np.random.default_rng(seed)
    returns, done = np.zeros(episodes), np.zeros(episodes, dtype=bool)
    while not done.all():
        move = policy(obs) if policy else rng.uniform(-1, 1, (episodes, 2)).astype(np.float32)
        obs, reward, terminated, truncated, _ = venv.step(move)
        returns += np.where(done, 0.0, reward)
        done |= terminated | truncated
    return float(returns.mean())


def test_ghost_ball_beats_random_over_100_episodes() -> None:
    """One object ball at a random spot, five shots: the ghost ball pots it nearly every
    time (measured 0.94), random play mostly scratches or misses (measured -1.8)."""
    scripted = _mean_return("Pool2D-v0", pool_ghost_ball, 100, 0, max_episode_steps=5)
    random = _mean_return("Pool2D-v0", None, 100, 0, max_episode_steps=5)
    assert scripted > 0.8 and scripted > random + 1.5


def test_ballistic_launch_beats_random_over_100_episodes() -> None:
    """Random levels (the default), three birds: aiming at the nearest pig scores 2.59 on
    average (measured; 2.99 on the hand-made levels), random launches 0.91."""
    scripted = _mean_return("Slingshot2D-v0", slingshot_ballistic, 100, 0)
    random = _mean_return("Slingshot2D-v0", None, 100, 0)
    assert scripted > 2.0 * random and scripted > 2.0


def test_ballistic_launch_beats_random_on_the_blocks_game() -> None:
    """Slingshot2DBlocks-v0's generated levels (roofs, stones, ramparts), three birds: the
    ballistic player reads the pigs from the same slots as in v0 and still scores far
    above random launches (measured 2.28 against 0.65; v0's levels give it 2.63)."""
    scripted = _mean_return("Slingshot2DBlocks-v0", slingshot_ballistic, 100, 0, level="random")
    random = _mean_return("Slingshot2DBlocks-v0", None, 100, 0, level="random")
    assert scripted > 2.5 * random and scripted > 1.8
