"""Training and evaluation of RL agents on the impulse2d games (Pool2D, Slingshot2D).

``python -m agents.train`` trains PPO or SAC (Stable-Baselines3) with hyperparameters from
``agents/hyperparams/<algo>.yml`` on the batched vector env, then evaluates the agent;
``python -m agents.evaluate`` compares a trained agent with the random and scripted players.
See ``agents/README.md``.
"""

from __future__ import annotations

from typing import Any

from ._config import ALGOS, ENV_IDS, algo_kwargs, resolve

# For scripts and notebooks that build the model themselves: ``resolve`` the YAML entry,
# ``make_vec_env`` the training env, ``PPO(config["policy"], venv, **algo_kwargs(config))``,
# and ``agent_policy(model)`` to play it as a batch policy.
__all__ = [
    "ALGOS",
    "ENV_IDS",
    "agent_policy",
    "algo_kwargs",
    "evaluate",
    "make_vec_env",
    "resolve",
    "train",
]


def __getattr__(name: str) -> Any:
    # Lazy, so that ``python -m agents.train`` does not find its own module already
    # imported by the package (runpy warns about that).
    if name == "train":
        from .train import train

        return train
    if name == "make_vec_env":
        from .train import make_vec_env

        return make_vec_env
    if name == "evaluate":
        from .evaluate import evaluate

        return evaluate
    if name == "agent_policy":
        from .evaluate import agent_policy

        return agent_policy
    raise AttributeError(f"module 'agents' has no attribute {name!r}")
