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
