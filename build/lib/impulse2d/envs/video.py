"""Videos of the shots: Gymnasium's ``RecordVideo`` and SB3's ``VecVideoRecorder``,
keeping every frame of each shot.

One ``step`` of these envs is a whole shot, seconds of motion. Made with
``render_mode="rgb_array_list"``, an env renders the shot at 30 frames per simulated
second, and ``render()`` hands them over; Gymnasium's ``RecordVideo`` takes only the
last frame of such a list into its video (the rest go to ``render_history``), so an
episode would be a few still pictures. ``RecordShotVideo`` is ``RecordVideo`` with that
one choice changed: every frame of the list goes into the video, so the balls roll.
Everything else (triggers, folders, names, fps from the env's metadata) is
``RecordVideo``'s. Writing the file needs moviepy, as ``RecordVideo`` does
(``pip install 'impulse2d[video]'``)::

    env = RecordShotVideo(gym.make("Pool2D-v0", render_mode="rgb_array_list"), "videos")

SB3's ``VecVideoRecorder`` likewise takes one tiled frame a step.
``impulse2d.envs.sb3.RecordShotVecVideo`` is that recorder taking every frame of the
step, over a vector env made with ``render_mode="rgb_array_list"`` (``video_length``
counts frames, as there)::

    venv = make_sb3_vec_env("Pool2D-v0", 4, seed=0, render_mode="rgb_array_list")
    venv = RecordShotVecVideo(venv, "videos", lambda step: step == 0, video_length=300)

Both record the shots as they were played: recording changes no result.
"""

from __future__ import annotations

import numpy as np
from gymnasium.wrappers import RecordVideo

__all__ = ["RecordShotVideo"]


class RecordShotVideo(RecordVideo):
    """``RecordVideo`` that records every frame an ``rgb_array_list`` render returns."""

    def _capture_frame(self) -> None:
        frames = self.env.render()
        if not isinstance(frames, list):
            raise ValueError(
                "RecordShotVideo needs an env made with render_mode='rgb_array_list' (the "
                f"frames of each shot), got render() of type {type(frames).__name__}"
            )
        # Not also kept in ``render_history`` (as RecordVideo does): a long recording would
        # hold every frame twice; ``render()`` afterwards returns only newer frames.
        self.recorded_frames += [frame for frame in frames if isinstance(frame, np.ndarray)]
