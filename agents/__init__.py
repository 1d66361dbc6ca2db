"""Training and evaluation of RL agents on Pool2D-v0 and Slingshot2D-v0.

``python -m agents.train`` trains PPO or SAC (Stable-Baselines3) with hyperparameters from
``agents/hyperparams/<algo>.yml`` on the batched vector env, then evaluates the agent;
``python -m agents.evaluate`` compares a trained agent with the random and scripted players.
See ``agents/README.md``.
"""

from __future__ import annotations

from typing import Any

from ._config import ALGOS, ENV_IDS, resolve

__all__ = ["ALGOS", "ENV_IDS", "evaluate", "resolve", "train"]


def __getattr__(name: str) -> Any:
    # Lazy, so that ``python -m agents.train`` does not find its own module already
    # imported by the package (runpy warns about that).
    if name == "train":
        from .train import train

        return train
    if name == "evaluate":
        from .evaluate import evaluate

        return evaluate
    raise AttributeError(f"module 'agents' has no attribute {name!r}")
