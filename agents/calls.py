"""Which pocket a trained one-ball call-shot agent calls, against the ghost-ball player's.

A score says how well an agent plays, not what it looks at. An agent that cannot see
the ball still scores: calling one pocket at a soft speed every time is worth 0.65 on
``Pool2DPixelsCallShot-v0`` (``bench/constant_calls.py``). What seeing adds is a call
that depends on the table. So this plays each run's first shot on the evaluation's
tables (the seeds ``agents.evaluate`` plays) and prints, per run, how often it calls each
pocket, how often its call is the ghost-ball player's pocket (the best clear shot by its
score, ``impulse2d.envs.bestshots``; on a table with none clear, the best blocked one)
and how often the called shot is clear at all; and
the same for the best fixed pocket, the blind player's ceiling on that count::

    python -m agents.calls runs/Pool2DPixelsCallShot-v0_ppo_seed0 [more runs]
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

import numpy as np

ONE_BALL_IDS = ("Pool2DCallShot-v0", "Pool2DPixelsCallShot-v0")


def first_calls(run_dir: str | Path, tables: int = 100, seed: int = 1000) -> dict[str, Any]:
    """The run's first call on tables seeded ``seed`` .. ``seed + tables - 1``:
    ``called`` and ``ghost`` (pocket indices, ``(tables,)``) and ``clear`` (whether the
    called shot is clear, ``(tables,)`` bool)."""
    import gymnasium as gym

    import impulse2d  # noqa: F401  (registers the ids)
    from impulse2d.envs.bestshots import table_shots

    from . import _config
    from .evaluate import load_policy

    tables = _config.positive_count("tables", tables)
    policy, config = load_policy(run_dir)  # deterministic, as agents.evaluate plays it
    if config["env_id"] not in ONE_BALL_IDS:
        raise ValueError(f"run_dir: a run of one of {ONE_BALL_IDS}, not {config['env_id']}")
    seeds = list(range(seed, seed + tables))
    kwargs = {**config["env_kwargs"], **config["eval_env_kwargs"]}  # as agents.evaluate plays
    venv = gym.make_vec(config["env_id"], tables, vectorization_mode="vector_entry_point", **kwargs)
    obs, _ = venv.reset(seed=seeds)
    shots = table_shots(venv.unwrapped.game.observe())  # one ball: its six pockets
    venv.close()
    called = np.argmax(policy(obs)[:, :6], axis=1)
    ghost = np.argmax(shots["score"] + 2.0 * shots["valid"], axis=1)
    return {"called": called, "ghost": ghost, "clear": shots["valid"][np.arange(tables), called]}


def table(runs: list[str], tables: int = 100, seed: int = 1000) -> str:
    """One row per run and one for the best fixed pocket (markdown)."""
    lines = ["| run | calls per pocket (0-5) | the ghost-ball player's pocket | clear shot |",
             "|---|---|---|---|"]  # fmt: skip
    ghost = None
    for run in runs:
        calls = first_calls(run, tables, seed)
        ghost = calls["ghost"]
        counts = " ".join(str(c) for c in np.bincount(calls["called"], minlength=6))
        match = int((calls["called"] == calls["ghost"]).sum())
        clear = int(calls["clear"].sum())
        lines.append(f"| {run} | {counts} | {match}/{tables} | {clear}/{tables} |")
    if ghost is not None:
        best = int(np.bincount(ghost, minlength=6).max())
        lines.append(f"| best fixed pocket | | {best}/{tables} | |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("runs", nargs="+", help="run directories made by agents.train")
    parser.add_argument("--tables", type=int, default=100)
    parser.add_argument("--seed", type=int, default=1000)
    args = parser.parse_args(argv)
    print(table(args.runs, args.tables, args.seed))


if __name__ == "__main__":
    main()
