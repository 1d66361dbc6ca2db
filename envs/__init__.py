"""Gymnasium environments on the impulse2d engine: ``Pool2D-v0`` and ``Slingshot2D-v0``,
and their learnable variants ``Pool2DOneBall-v0`` and ``Slingshot2DHandmade-v0``.

``import impulse2d`` registers them (when gymnasium is installed), and so does
``gym.make("impulse2d:Pool2D-v0")`` in a fresh process. Each id also has a vector entry
point that steps all its worlds in one batched engine:
``gym.make_vec("Pool2D-v0", num_envs=256, vectorization_mode="vector_entry_point")``.
"""

from __future__ import annotations

from typing import Any

# Slingshot2DBlocks-v0 is Slingshot2D with triangles and round stones (envs/slingshot_blocks.py).
IDS = ("Pool2D-v0", "Slingshot2D-v0", "Slingshot2DBlocks-v0")
# The learnable variants, for tools that take only an id (RL Zoo, CleanRL, TorchRL): the
# first pool task of docs/getting-started.md (one object ball at a random spot, five
# shots an episode) and the hand-made slingshot levels. Each is its base game with these
# keyword arguments.
VARIANTS = {
    "Pool2DOneBall-v0": ("Pool2D-v0", {"num_balls": 1, "layout": "random"}, 5),
    "Slingshot2DHandmade-v0": ("Slingshot2D-v0", {"level": "handmade"}, 10),
}


# The call-shot tasks (``impulse2d.envs.callshot``): a game and its arguments under a
# wrapper whose action names the shot. What ``python -m agents.train`` trains, by id.
CALL_SHOT_IDS = {
    "Pool2DCallShot-v0": ("Pool2D-v0", {"num_balls": 1, "layout": "random"}, 5),
    "Pool2DRackCallShot-v0": ("Pool2D-v0", {"num_balls": 15, "layout": "rack"}, 30),
    # The rack again, the call among the table's six best shots rather than the nearest
    # ball's six pockets (impulse2d.envs.bestshots).
    "Pool2DRackBestShots-v0": ("Pool2D-v0", {"num_balls": 15, "layout": "rack"}, 30),
    # The first task seen, not told: the table as a 64 x 64 image, no features.
    "Pool2DPixelsCallShot-v0": (
        "Pool2D-v0",
        {"num_balls": 1, "layout": "random", "obs_type": "pixels", "pixel_size": 64},
        5,
    ),
    "Slingshot2DCallShot-v0": ("Slingshot2D-v0", {"level": "handmade"}, 10),
    "Slingshot2DGeneratedCallShot-v0": (
        "Slingshot2D-v0",
        {"level": "random", "num_levels": 4000},
        10,
    ),
    # PHYRE's task: one bird a level, of the seven train templates (envs/_templates.py);
    # agents.protocol scores it on unseen levels of those and on the held-out templates.
    "Slingshot2DTemplatesCallShot-v0": (
        "Slingshot2D-v0",
        {"level": "templates", "templates": "train", "num_levels": 4000, "num_birds": 1},
        10,
    ),
    # The generated levels with triangles and stones, as Slingshot2DGeneratedCallShot-v0.
    "Slingshot2DBlocksCallShot-v0": (
        "Slingshot2DBlocks-v0",
        {"level": "random", "num_levels": 4000},
        10,
    ),
}


# Entry points of the call-shot ids that are not their game's plain call-shot wrapper.
CALL_SHOT_ENTRY_POINTS = {
    "Pool2DRackBestShots-v0": (
        "impulse2d.envs.bestshots:make",
        "impulse2d.envs.bestshots:make_vector",
    ),
    "Slingshot2DBlocksCallShot-v0": (
        "impulse2d.envs.slingshot_blocks:make_call_shot",
        "impulse2d.envs.slingshot_blocks:make_call_shot_vector",
    ),
}


def base_game(env_id: str) -> tuple[str, dict[str, Any]]:
    """The game id and keyword arguments under a registered id (``Pool2DCallShot-v0`` ->
    ``("Pool2D-v0", {"num_balls": 1, "layout": "random"})``; a game's own id -> itself)."""
    for table in (VARIANTS, CALL_SHOT_IDS):
        if env_id in table:
            base, kwargs, _ = table[env_id]
            return base, dict(kwargs)
    if env_id in IDS:
        return env_id, {}
    raise ValueError(f"env_id must be one of {all_ids()}, got {env_id!r}")


def all_ids() -> list[str]:
    """Every id this package registers."""
    return [*IDS, *VARIANTS, *CALL_SHOT_IDS]


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
    gym.register(
        id="Slingshot2DBlocks-v0",
        entry_point="impulse2d.envs.slingshot_blocks:Slingshot2DBlocksEnv",
        vector_entry_point="impulse2d.envs.slingshot_blocks:Slingshot2DBlocksVectorEnv",
        max_episode_steps=10,
    )
    for variant, (base, kwargs, max_steps) in VARIANTS.items():
        spec = gym.spec(base)
        gym.register(
            id=variant,
            entry_point=spec.entry_point,
            vector_entry_point=spec.vector_entry_point,
            max_episode_steps=max_steps,
            kwargs=kwargs,
        )
    entry = {"Pool2D-v0": "pool", "Slingshot2D-v0": "slingshot"}
    for task, (base, kwargs, max_steps) in CALL_SHOT_IDS.items():
        if task in CALL_SHOT_ENTRY_POINTS:
            single, vector = CALL_SHOT_ENTRY_POINTS[task]
        else:
            name = entry[base]
            single = f"impulse2d.envs.callshot:make_{name}"
            vector = f"impulse2d.envs.callshot:make_{name}_vector"
        gym.register(
            id=task,
            entry_point=single,
            vector_entry_point=vector,
            max_episode_steps=max_steps,
            kwargs=kwargs,
        )
