"""Gymnasium environments on the impulse2d engine: ``Pool2D-v0`` and ``Slingshot2D-v0``.

``import impulse2d`` registers both (when gymnasium is installed), and so does
``gym.make("impulse2d:Pool2D-v0")`` in a fresh process. Each id also has a vector entry
point that steps all its worlds in one batched engine:
``gym.make_vec("Pool2D-v0", num_envs=256, vectorization_mode="vector_entry_point")``.
"""

from __future__ import annotations

IDS = ("Pool2D-v0", "Slingshot2D-v0")


def register() -> None:
    """Register the environments with gymnasium (once; later calls do nothing)."""
    import gymnasium as gym

    if "Pool2D-v0" in gym.registry:
        return
    gym.register(
        id="Pool2D-v0",
        entry_point="impulse2d.envs.pool:Pool2DEnv",
        vector_entry_point="impulse2d.envs.pool:Pool2DVectorEnv",
        max_episode_steps=30,
    )
    gym.register(
        id="Slingshot2D-v0",
        entry_point="impulse2d.envs.slingshot:Slingshot2DEnv",
        vector_entry_point="impulse2d.envs.slingshot:Slingshot2DVectorEnv",
        max_episode_steps=10,
    )
