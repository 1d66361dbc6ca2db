"""Two shots of the Pool2D-v0 and Slingshot2D-v0 vector envs on the device named on the
command line; prints a digest of their observations, rewards and endings
(``test_gpu.py`` runs it with ``cuda`` in numba's CUDA simulator and with ``cpu``)."""

import hashlib
import sys

import gymnasium as gym
import numpy as np

import impulse2d  # noqa: F401  (registers the ids)


def digest(env_id: str, device: str, **options: object) -> str:
    env = gym.make_vec(env_id, 3, vectorization_mode="vector_entry_point", device=device,
                       max_shot_seconds=1.5, **options)  # fmt: skip
    assert env.unwrapped.game.world.device == device
    obs, _ = env.reset(seed=5)
    seen = hashlib.sha256(obs.tobytes())
    actions = np.random.default_rng(5).uniform(-1, 1, (2, *env.action_space.shape))
    for action in actions.astype(np.float32):
        obs, reward, terminated, truncated, _ = env.step(action)
        for array in (obs, reward, terminated, truncated):
            seen.update(np.ascontiguousarray(array).tobytes())
    return seen.hexdigest()[:16]


if __name__ == "__main__":
    device = sys.argv[1]
    print(digest("Pool2D-v0", device, num_balls=2), digest("Slingshot2D-v0", device))
