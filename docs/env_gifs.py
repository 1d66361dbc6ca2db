"""Make the animations of the two games played by their scripted baselines (the README's
and the games' pages in docs/envs/).

``python docs/env_gifs.py`` (needs the ``demo`` and ``envs`` extras) writes
``docs/pool2d-ghost-ball.gif`` (Pool2D-v0, the 15-ball rack, the first shots of the
ghost-ball player) and ``docs/slingshot2d-ballistic.gif`` (Slingshot2D-v0, a hand-made
level, the ballistic player), from the ``rgb_array_list`` frames at 30 per simulated
second, every second frame kept (the pool table at half size); and
``docs/slingshot2dblocks-levels.png``, Slingshot2DBlocks-v0's three hand-made levels with
triangles and stones, as they start, one above the other.
"""

from __future__ import annotations

from pathlib import Path

import gymnasium as gym
import imageio.v3 as iio
import numpy as np

import impulse2d  # noqa: F401  (registers the environments)
from impulse2d.envs.baselines import pool_ghost_ball, slingshot_ballistic

HERE = Path(__file__).parent


def play(env_id: str, policy, shots: int, seed: int, scale: int, **options) -> list[np.ndarray]:
    env = gym.make(env_id, render_mode="rgb_array_list", **options)
    obs, _ = env.reset(seed=seed)
    frames: list[np.ndarray] = []
    for _ in range(shots):
        obs, _, terminated, truncated, _ = env.step(policy(obs))
        frames += env.render()
        if terminated or truncated:
            break
    env.close()
    return [frame[::scale, ::scale] for frame in frames[::2]]


def blocks_levels() -> np.ndarray:
    """Slingshot2DBlocks-v0's hut, boulder and ramparts at the start, stacked: the lowest
    120 rows of each 480 x 270 frame (the ground and 4 m of sky)."""
    frames = []
    for level in ("hut", "boulder", "ramparts"):
        env = gym.make("Slingshot2DBlocks-v0", level=level, render_mode="rgb_array")
        env.reset(seed=0)
        frames.append(env.render()[-120:])
        env.close()
    return np.concatenate(frames, axis=0)


def main() -> None:
    iio.imwrite(HERE / "slingshot2dblocks-levels.png", blocks_levels())
    pool = play("Pool2D-v0", pool_ghost_ball, shots=4, seed=3, scale=2)
    iio.imwrite(HERE / "pool2d-ghost-ball.gif", np.stack(pool), duration=1000 / 15, loop=0)
    sling = play("Slingshot2D-v0", slingshot_ballistic, shots=3, seed=1, scale=1, level="tower")
    iio.imwrite(HERE / "slingshot2d-ballistic.gif", np.stack(sling), duration=1000 / 15, loop=0)


if __name__ == "__main__":
    main()
