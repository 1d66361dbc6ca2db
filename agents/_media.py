"""The pictures of an evaluation: the learning curve (PNG) and the agent playing (GIF/MP4)."""

from __future__ import annotations

import csv
import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

VIDEO_FPS = 15  # the env renders 30 frames per simulated second; every second one is kept


def read_progress(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """``time/total_timesteps`` and ``rollout/ep_rew_mean`` from SB3's ``progress.csv``
    (rows without an episode mean, e.g. before the first episode ends, are skipped)."""
    steps, rewards = [], []
    if path.is_file():
        with open(path, newline="") as file:
            for row in csv.DictReader(file):
                step, reward = row.get("time/total_timesteps"), row.get("rollout/ep_rew_mean")
                if step and reward:
                    steps.append(float(step))
                    rewards.append(float(reward))
    return np.array(steps), np.array(rewards)


def learning_curve(
    run_dir: Path,
    out: Path,
    title: str,
    baselines: dict[str, float],
    trained: tuple[float, float] | None = None,
    skip_before: int = 0,
) -> bool:
    """Plot the mean training-episode return against env steps, with the baselines'
    evaluation means as horizontal lines and the trained agent's evaluation (mean ± std of
    the mean) at the end. Returns False (and draws nothing) if there is no data.

    Rows before ``skip_before`` steps are left out: until every world has had time to
    finish an episode, the finished ones are the short ones (in Pool, the pots), and their
    mean says little about the policy."""
    steps, rewards = read_progress(run_dir / "progress.csv")
    keep = steps >= skip_before
    if keep.any():
        steps, rewards = steps[keep], rewards[keep]
    if steps.size == 0:
        return False
    plt, fig, ax = reward_axes(title, baselines)
    ax.plot(steps, rewards, color="tab:blue", label="training episodes (recent mean)")
    if trained is not None:
        ax.errorbar(
            [steps[-1]],
            [trained[0]],
            yerr=[trained[1]],
            fmt="o",
            color="tab:blue",
            capsize=4,
            label="trained agent, evaluated (mean ± s.e.)",
        )
    ax.legend(fontsize=8, loc="best")
    save_figure(plt, fig, out)
    return True


def reward_axes(title: str, baselines: dict[str, float]) -> tuple[Any, Any, Any]:
    """pyplot (headless), a figure and its axes of reward against env steps, with the
    baselines' evaluation means as dashed lines (random red, random call-shot actions
    orange, scripted green)."""
    import matplotlib

    matplotlib.use("Agg")  # files only, no display
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4), dpi=110)
    for name, value in baselines.items():
        colour = "tab:red" if name.startswith("random") else "tab:green"
        colour = "tab:orange" if name.startswith("random call-shot") else colour
        ax.axhline(value, ls="--", color=colour, label=name)
    ax.set_xlabel("env steps (shots)")
    ax.set_ylabel("reward / episode")
    ax.set_title(title)
    ax.grid(alpha=0.3)
    return plt, fig, ax


def save_figure(plt: Any, fig: Any, out: Path) -> None:
    fig.tight_layout()
    fig.savefig(out)
    plt.close(fig)


def seed_curves(
    runs: list[tuple[Path, str, float]],
    out: Path,
    title: str,
    baselines: dict[str, float],
    skip_before: int = 0,
) -> bool:
    """Several training runs of one config in one plot: each run's mean training-episode
    return against env steps (``runs``: run directory, label, evaluated mean reward, drawn
    as a dot at the end of its curve), and the baselines' evaluation means as lines.
    Returns False (and draws nothing) if no run has data."""
    curves = []
    for run_dir, label, evaluated in runs:
        steps, rewards = read_progress(run_dir / "progress.csv")
        keep = steps >= skip_before
        if keep.any():
            curves.append((steps[keep], rewards[keep], label, evaluated))
    if not curves:
        return False
    plt, fig, ax = reward_axes(title, baselines)
    for index, (steps, rewards, label, evaluated) in enumerate(curves):
        colour = plt.get_cmap("Blues")(0.45 + 0.5 * index / max(1, len(curves) - 1))
        ax.plot(steps, rewards, color=colour, lw=1.2, label=f"{label}: training episodes")
        ax.plot([steps[-1]], [evaluated], "o", color=colour, label=f"{label}: evaluated")
    ax.legend(fontsize=7, loc="lower right", ncol=2)  # the curves rise to the top right
    save_figure(plt, fig, out)
    return True


def record_video(
    env_id: str,
    env_kwargs: dict[str, Any],
    policy: Callable[[np.ndarray], np.ndarray],
    out: Path,
    seed: int,
    shots: int = 6,
    max_frames: int = 450,
) -> int:
    """Play single-env episodes from ``seed`` until ``shots`` shots are played (finishing
    no episode early), render them (``rgb_array_list``: the frames during each shot) and
    write ``out`` (``.gif`` or ``.mp4``). Returns the number of frames written."""
    import gymnasium as gym
    import imageio.v3 as iio

    import impulse2d  # noqa: F401  (registers the env ids)

    kwargs = {k: v for k, v in env_kwargs.items() if k != "max_episode_steps"}
    env = gym.make(env_id, render_mode="rgb_array_list", **kwargs)
    frames: list[np.ndarray] = []
    played, episode = 0, 0
    while played < shots and len(frames) < max_frames:
        obs, _ = env.reset(seed=seed + episode)
        episode += 1
        limit = env_kwargs.get("max_episode_steps", math.inf)
        moves, finished = 0, False
        while not finished and played < shots and moves < limit:
            obs, _, terminated, truncated, _ = env.step(policy(obs[None])[0])
            moves, played = moves + 1, played + 1
            finished = terminated or truncated
            shot = env.render()
            frames += shot[::2]
            frames += [shot[-1]] * (VIDEO_FPS // 2)  # hold the result for half a second
    env.close()
    frames = frames[:max_frames]
    if out.suffix == ".mp4":
        iio.imwrite(out, np.stack(frames), fps=VIDEO_FPS, macro_block_size=2)
    else:
        iio.imwrite(out, np.stack(frames), duration=1000 / VIDEO_FPS, loop=0)
    return len(frames)
