"""Videos of episodes show the motion: ``RecordShotVideo`` (Gymnasium's ``RecordVideo``
over ``render_mode="rgb_array_list"``) writes every frame of each shot, where
``RecordVideo`` itself keeps one frame a step."""

from __future__ import annotations

import gymnasium as gym
import imageio.v3 as iio
import numpy as np
from gymnasium.wrappers import RecordVideo

import impulse2d  # noqa: F401  (registers the ids)
from impulse2d.envs.video import RecordShotVideo


def _record(wrapper: type, folder) -> tuple[int, int]:
    """Frames in the video of a one-shot episode, and the shot's physics steps."""
    env = wrapper(
        gym.make("Pool2D-v0", num_balls=1, max_episode_steps=1, render_mode="rgb_array_list"),
        str(folder / "videos"),  # a new folder: RecordVideo warns about existing ones
        disable_logger=True,
    )
    env.reset(seed=0)
    *_, info = env.step(np.array([0.1, 0.3], np.float32))
    env.close()
    (video,) = (folder / "videos").glob("*.mp4")
    return iio.imread(video).shape[0], info["physics_steps"]


def test_the_video_of_a_shot_has_its_frames_at_30_per_simulated_second(tmp_path):
    frames, steps = _record(RecordShotVideo, tmp_path)
    # The frame after the reset, one every 1/30 s of the shot (dt 1/120), the one after it.
    expected = 1 + steps // 4 + 1
    assert abs(frames - expected) <= 1 and frames >= 10


def test_gymnasiums_record_video_alone_keeps_one_frame_a_step(tmp_path):
    frames, _ = _record(RecordVideo, tmp_path)
    assert frames <= 2  # why RecordShotVideo exists


def _shot_frames_and_obs(render_mode: str | None, num_envs: int = 2):
    """A vector env's frames (``render()`` after reset and after one shot) and obs."""
    venv = gym.make_vec(
        "Pool2D-v0",
        num_envs,
        vectorization_mode="vector_entry_point",
        num_balls=1,
        render_mode=render_mode,
    )
    obs0, _ = venv.reset(seed=3)
    at_reset = venv.render()
    obs1, *_ = venv.step(np.array([[0.1, 0.3], [-0.4, 0.8]][:num_envs], np.float32))
    after_shot = venv.render()
    venv.close()
    return at_reset, after_shot, (obs0, obs1)


def test_the_vector_env_renders_every_world_during_the_shots():
    at_reset, shot, obs = _shot_frames_and_obs("rgb_array_list")
    assert len(at_reset) == len(shot) == 2 and [len(f) for f in at_reset] == [1, 1]
    assert len(shot[0]) == len(shot[1]) >= 10  # one length: the worlds move together
    assert all(f.shape == (270, 480, 3) and f.dtype == np.uint8 for f in shot[0] + shot[1])
    assert not np.array_equal(shot[0][1], shot[0][-1])  # the ball moved
    assert not np.array_equal(shot[0][-1], shot[1][-1])  # two different tables
    assert venv_render_is_taken()
    # The last frame of each list is the rgb_array frame after the shot, and recording
    # changes no observation.
    _, still, plain_obs = _shot_frames_and_obs("rgb_array")
    for world in (0, 1):
        assert np.array_equal(shot[world][-1], still[world])
    for recorded, plain in zip(obs, plain_obs, strict=True):
        assert np.array_equal(recorded, plain)


def venv_render_is_taken() -> bool:
    """A second render() right after one gives empty lists (frames are handed over once)."""
    venv = gym.make_vec(
        "Pool2D-v0", 2, vectorization_mode="vector_entry_point", render_mode="rgb_array_list"
    )
    venv.reset(seed=0)
    first, second = venv.render(), venv.render()
    venv.close()
    return [len(f) for f in first] == [1, 1] and [len(f) for f in second] == [0, 0]


def test_a_vector_env_of_one_world_draws_the_single_envs_frames():
    at_reset, shot, _ = _shot_frames_and_obs("rgb_array_list", num_envs=1)
    env = gym.make("Pool2D-v0", num_balls=1, render_mode="rgb_array_list")
    env.reset(seed=3)
    single_reset = env.render()
    env.step(np.array([0.1, 0.3], np.float32))
    single_shot = env.render()
    env.close()
    for vector_frames, single_frames in ((at_reset[0], single_reset), (shot[0], single_shot)):
        assert len(vector_frames) == len(single_frames)
        assert all(np.array_equal(a, b) for a, b in zip(vector_frames, single_frames, strict=True))


def _record_sb3(recorder: type, folder, shots: int = 2) -> tuple[int, int, list]:
    """Frames in SB3's video of ``shots`` steps of two tables, their frame count from
    ``shot_frames``, and the observations seen."""
    from impulse2d.envs.sb3 import make_sb3_vec_env

    venv = make_sb3_vec_env("Pool2D-v0", 2, seed=0, num_balls=1, render_mode="rgb_array_list")
    venv = recorder(venv, str(folder / "videos"), lambda step: step == 0, video_length=10_000)
    seen = [venv.reset()]
    expected = len(venv.shot_frames())
    for _ in range(shots):
        seen.append(venv.step(np.array([[0.1, 0.3], [-0.4, 0.8]], np.float32))[0])
        expected += len(venv.shot_frames())
    venv.close()
    (video,) = (folder / "videos").glob("*.mp4")
    return iio.imread(video).shape[0], expected, seen


def test_sb3_videos_of_the_shots_keep_every_frame(tmp_path):
    from stable_baselines3.common.vec_env import VecVideoRecorder

    from impulse2d.envs.sb3 import RecordShotVecVideo

    frames, expected, seen = _record_sb3(RecordShotVecVideo, tmp_path / "shots")
    assert abs(frames - expected) <= 1 and frames >= 20
    plain_frames, _, plain_seen = _record_sb3(VecVideoRecorder, tmp_path / "plain")
    assert plain_frames <= 3  # SB3's recorder alone: one tiled frame a step
    for a, b in zip(seen, plain_seen, strict=True):
        assert np.array_equal(a, b)  # recording changes no observation
    (video,) = (tmp_path / "shots" / "videos").glob("*.mp4")
    assert iio.imread(video).shape[1] >= 2 * 270 - 16  # two tables, tiled as SB3 tiles them


def test_shot_frames_and_the_recorder_name_what_they_need(tmp_path):
    import pytest

    from impulse2d.envs.sb3 import RecordShotVecVideo, make_sb3_vec_env

    venv = make_sb3_vec_env("Pool2D-v0", 2, seed=0, render_mode="rgb_array")
    with pytest.raises(ValueError, match="render_mode='rgb_array_list'"):
        venv.shot_frames()
    from stable_baselines3.common.vec_env import DummyVecEnv

    dummy = DummyVecEnv([lambda: gym.make("Pool2D-v0", render_mode="rgb_array")])
    recorder = RecordShotVecVideo(dummy, str(tmp_path / "v"), lambda step: step == 0)
    with pytest.raises(ValueError, match="needs an SB3VecEnv"):
        recorder.reset()
