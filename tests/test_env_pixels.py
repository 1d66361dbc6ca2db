"""The envs seen as pixels (``obs_type="pixels"``): both checkers, vector env ``i`` as the
single env seeded ``seed + i``, what the frame shows against the state (the cue ball
where the state puts it, a potted ball gone, the birds left), saved states, SB3's CNN
policy, and the call-shot tasks refusing it."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env
from stable_baselines3 import PPO
from stable_baselines3.common.env_checker import check_env as sb3_check_env

import impulse2d  # noqa: F401  (registers the ids)
from impulse2d.envs.pool import BALL_COLOURS
from impulse2d.envs.sb3 import make_sb3_vec_env

IDS = ("Pool2D-v0", "Slingshot2D-v0", "Slingshot2DBlocks-v0")
FAST = {"max_shot_seconds": 2.0}


@pytest.mark.parametrize("env_id", IDS)
def test_both_checkers_pass(env_id):
    env = gym.make(env_id, obs_type="pixels", **FAST)
    check_env(env.unwrapped, skip_render_check=True)
    sb3_check_env(env.unwrapped)
    obs, _ = env.reset(seed=0)
    assert obs.shape == (84, 84, 3) and obs.dtype == np.uint8
    assert env.observation_space == gym.spaces.Box(0, 255, (84, 84, 3), np.uint8)


@pytest.mark.parametrize("env_id", IDS)
def test_vector_env_i_is_the_single_env_seeded_seed_plus_i(env_id):
    vector = gym.make_vec(env_id, 3, vectorization_mode="vector_entry_point",
                          obs_type="pixels", pixel_size=48, **FAST)  # fmt: skip
    actions = np.random.default_rng(1).uniform(-1, 1, (2, 3, 2)).astype(np.float32)
    seen = [vector.reset(seed=7)[0]] + [vector.step(a)[0] for a in actions]
    assert seen[0].shape == (3, 48, 48, 3) and vector.observation_space.contains(seen[1])
    for i in range(3):
        single = gym.make(env_id, obs_type="pixels", pixel_size=48, **FAST)
        alone = [single.reset(seed=7 + i)[0]] + [single.step(a[i])[0] for a in actions]
        for batch, one in zip(seen, alone, strict=True):
            assert np.array_equal(batch[i], one)
    assert not np.array_equal(seen[0], seen[2])  # the shots moved something


def _blob(frame: np.ndarray, colour: tuple[int, int, int]) -> tuple[float, float, float]:
    """Weight, centroid (x, y in pixels) of the pixels close to ``colour``."""
    near = np.abs(frame.astype(int) - np.array(colour)).sum(axis=2) < 60
    rows, cols = np.nonzero(near)
    if rows.size == 0:
        return 0.0, float("nan"), float("nan")
    return float(near.sum()), float(cols.mean() + 0.5), float(rows.mean() + 0.5)


def test_the_pool_frame_shows_the_cue_ball_where_the_state_puts_it():
    env = gym.make("Pool2D-v0", obs_type="pixels", num_balls=1, pixel_size=128)
    frame, _ = env.reset(seed=3)
    game = env.unwrapped.game
    cue = game.balls[0].position
    frames = game._frames[128]
    weight, x, y = _blob(frame, BALL_COLOURS[0])
    assert weight >= 3
    assert (x, y) == pytest.approx(frames.to_pixels(*cue), abs=0.6)


def test_a_potted_ball_leaves_the_frame():
    """A straight shot at a ball on the pocket's line: potted, it is switched off, and
    the frame no longer shows its colour."""
    env = gym.make("Pool2D-v0", obs_type="pixels", num_balls=1, pixel_size=128)
    env.reset(seed=0)
    game = env.unwrapped.game
    object_ball = game.balls[1]
    colour = BALL_COLOURS[1]
    assert _blob(env.unwrapped._view.observe(game)[0], colour)[0] > 0
    object_ball.enabled = False  # as a pocket leaves it
    assert np.all(np.abs(game.pixels(128)[0].astype(int) - colour).sum(axis=2) >= 60)


def test_the_slingshot_frame_counts_the_birds_left():
    """At the top left, one red dot for each bird left: three at the start, two after a
    launch (the patch pasted for that count)."""
    env = gym.make("Slingshot2D-v0", obs_type="pixels", num_birds=3, pixel_size=160)
    frame, _ = env.reset(seed=1)
    game = env.unwrapped.game
    rows, cols, by_count = game._bird_patches[160]
    red = (210, 40, 40)
    assert [_blob(patch, red)[0] > 0 for patch in by_count] == [False, True, True, True]
    assert np.array_equal(frame[rows, cols], by_count[3])
    frame, *_ = env.step(np.array([0.5, 0.0], np.float32))
    assert game.birds_left[0] == 2 and np.array_equal(frame[rows, cols], by_count[2])
    assert _blob(by_count[3], red)[0] > _blob(by_count[2], red)[0]


def test_a_saved_state_brings_back_the_frame():
    env = gym.make("Pool2D-v0", obs_type="pixels", **FAST).unwrapped
    first, _ = env.reset(seed=4)
    saved = env.save_state()
    env.step(np.array([0.1, 0.9], np.float32))
    assert np.array_equal(env.restore_state(saved), first)


def test_sb3_ppo_with_the_cnn_policy_learns_a_few_steps():
    venv = make_sb3_vec_env("Pool2D-v0", 4, seed=0, obs_type="pixels", num_balls=1, **FAST)
    model = PPO("CnnPolicy", venv, n_steps=8, batch_size=16, n_epochs=1, seed=0, device="cpu")
    model.learn(32)
    assert model.num_timesteps == 32


@pytest.mark.parametrize("env_id", ["Pool2DCallShot-v0", "Slingshot2DCallShot-v0"])
def test_the_call_shot_tasks_see_pixels_and_play_the_same_game(env_id):
    """With pixels a call-shot env observes the game's frames (no features), and its
    actions play exactly the shots they play with state observations."""
    venvs = [
        gym.make_vec(env_id, 3, vectorization_mode="vector_entry_point", obs_type=kind)
        for kind in ("state", "pixels")
    ]
    state, pixels = venvs
    assert pixels.single_observation_space == gym.spaces.Box(0, 255, (84, 84, 3), np.uint8)
    assert state.single_observation_space.shape != pixels.single_observation_space.shape
    _, _ = state.reset(seed=5)
    frames, _ = pixels.reset(seed=5)
    assert frames.shape == (3, 84, 84, 3) and frames.dtype == np.uint8
    np.testing.assert_array_equal(frames, pixels.unwrapped.game.pixels(84))
    rng = np.random.default_rng(0)
    for _ in range(2):
        actions = rng.uniform(-1, 1, (3, *state.single_action_space.shape)).astype(np.float32)
        a = state.step(actions)
        b = pixels.step(actions)
        np.testing.assert_array_equal(a[1], b[1])  # rewards
        np.testing.assert_array_equal(a[2], b[2])
        np.testing.assert_array_equal(
            state.unwrapped.game.world.array("pose"), pixels.unwrapped.game.world.array("pose")
        )
    single = gym.make(env_id, obs_type="pixels", pixel_size=32)
    frame, _ = single.reset(seed=1)
    assert frame.shape == (32, 32, 3) and single.observation_space.contains(frame)
