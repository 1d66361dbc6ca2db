"""Scripted players against random play: mean return over seeded episodes, as a table.

For each game variant, ``--episodes`` episodes (env ``i`` of a vector env seeded
``--seed``, so episode ``i`` is the single env seeded ``seed + i``) are played once by
the scripted baseline of ``impulse2d.envs.baselines`` and once by uniform random actions
(a numpy generator seeded ``--seed``). Every episode is played to its end (termination
or the episode's step limit). Prints mean ± standard deviation of the return, the
difference scripted - random and the ratio scripted / random (only where random play
scores above zero; pool's fouls make it negative).

Run: ``python bench/baseline_scores.py`` (about 10 seconds on 2 cores), ``--quick`` for
the first row only.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from typing import Any

import gymnasium as gym
import numpy as np

import impulse2d  # noqa: F401  (registers the environments)
from impulse2d.envs.baselines import pool_ghost_ball, slingshot_ballistic

Policy = Callable[[np.ndarray], np.ndarray] | None

VARIANTS: list[tuple[str, str, dict[str, Any], str, Policy]] = [
    (
        "Pool2D-v0, 1 ball, 5 shots",
        "Pool2D-v0",
        {"num_balls": 1, "max_episode_steps": 5},
        "ghost ball",
        pool_ghost_ball,
    ),
    (
        "Pool2D-v0, 15-ball rack, 30 shots",
        "Pool2D-v0",
        {},
        "ghost ball",
        pool_ghost_ball,
    ),
    ("Slingshot2D-v0, random levels", "Slingshot2D-v0", {}, "ballistic", slingshot_ballistic),
    (
        "Slingshot2D-v0, hand-made levels",
        "Slingshot2D-v0",
        {"level": "handmade"},
        "ballistic",
        slingshot_ballistic,
    ),
]


def returns(env_id: str, options: dict[str, Any], policy: Policy, episodes: int, seed: int):
    """The return of the first episode of each of ``episodes`` envs."""
    venv = gym.make_vec(env_id, episodes, vectorization_mode="vector_entry_point", **options)
    obs, _ = venv.reset(seed=seed)
    rng = np.random.default_rng(seed)
    total, done = np.zeros(episodes), np.zeros(episodes, dtype=bool)
    while not done.all():
        if policy is None:
            action = rng.uniform(-1.0, 1.0, (episodes, 2)).astype(np.float32)
        else:
            action = policy(obs)
        obs, reward, terminated, truncated, _ = venv.step(action)
        total += np.where(done, 0.0, reward)
        done |= terminated | truncated
    venv.close()
    return total


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=100)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--quick", action="store_true", help="only the first variant")
    args = parser.parse_args(argv)
    if args.episodes < 1:
        raise SystemExit(f"--episodes must be >= 1, got {args.episodes}")
    print(f"{args.episodes} episodes per row, seeds {args.seed}..{args.seed + args.episodes - 1}")
    print("| variant | scripted | scripted return | random return | difference | ratio |")
    print("|---|---|---|---|---|---|")
    for name, env_id, options, player, policy in VARIANTS[: 1 if args.quick else None]:
        scripted = returns(env_id, options, policy, args.episodes, args.seed)
        rand = returns(env_id, options, None, args.episodes, args.seed)
        ratio = f"{scripted.mean() / rand.mean():.2f}" if rand.mean() > 0 else "n/a"
        print(
            f"| {name} | {player} | {scripted.mean():.2f} ± {scripted.std():.2f} "
            f"| {rand.mean():.2f} ± {rand.std():.2f} | {scripted.mean() - rand.mean():+.2f} "
            f"| {ratio} |",
            flush=True,
        )


if __name__ == "__main__":
    main()
