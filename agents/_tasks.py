"""What evaluation needs to know about each env: its scripted player, how to play a batch
of seeded episodes, and the task metrics of the comparison table.

Episodes are played on the batched vector env: env ``i`` of a batch reset with ``seed`` is
seeded ``seed + i``, and only its first episode counts, so every policy (trained, random,
scripted) meets exactly the same starting positions, whatever the policy does.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

Policy = Callable[[np.ndarray], np.ndarray]


@dataclass(frozen=True)
class Metric:
    """One column of the table. ``kind``: ``"episode"`` (mean ± std over episodes of
    ``value(record)``, an array with one entry per episode) or ``"rate"`` (one number for
    the whole evaluation: the ratio of two totals, e.g. pots per shot)."""

    key: str
    label: str
    kind: str
    value: Callable[[dict[str, np.ndarray]], Any]


@dataclass(frozen=True)
class Target:
    """A target of the issues (agents/README.md): the trained agent's mean of ``metric`` is
    at least ``factor`` times that of the ``against`` player (``"random"`` or
    ``"scripted"``). Against random, also above 0: twice a negative score is no bar."""

    name: str
    metric: str
    factor: float
    against: str


@dataclass(frozen=True)
class Task:
    env_id: str
    scripted_name: str
    scripted: Policy
    metrics: tuple[Metric, ...]
    targets: tuple[Target, ...]


def _ratio(num: str, den: str) -> Callable[[dict[str, np.ndarray]], float]:
    return lambda r: float(r[num].sum() / max(r[den].sum(), 1))


def _episode(key: str) -> Callable[[dict[str, np.ndarray]], np.ndarray]:
    return lambda r: r[key].astype(np.float64)


REWARD = Metric("reward", "reward / episode", "episode", _episode("return"))


def _pool() -> Task:
    from impulse2d.envs.baselines import pool_ghost_ball

    return Task(
        env_id="Pool2D-v0",
        scripted_name="ghost ball",
        scripted=pool_ghost_ball,
        metrics=(
            REWARD,
            Metric("potted", "potted / episode", "episode", _episode("potted")),
            Metric("potted_per_shot", "potted / shot", "rate", _ratio("potted", "shots")),
            Metric("fouls_per_shot", "fouls / shot", "rate", _ratio("fouls", "shots")),
            Metric("scratches_per_shot", "scratches / shot", "rate", _ratio("cue_potted", "shots")),
            Metric("shots", "shots / episode", "episode", _episode("shots")),
        ),
        targets=(
            # Per shot: pots per episode saturate (the 15-ball game ends at 15, and random
            # play pots half the rack in 30 shots), and the reward can be negative.
            Target("beats_random_2x", "potted_per_shot", 2.0, "random"),
            Target("half_of_scripted", "reward", 0.5, "scripted"),
            Target("pots_half_of_scripted", "potted", 0.5, "scripted"),
            Target("matches_scripted", "reward", 1.0, "scripted"),
        ),
    )


def _slingshot(env_id: str) -> Task:
    from impulse2d.envs.baselines import slingshot_ballistic

    return Task(
        env_id=env_id,
        scripted_name="ballistic",
        scripted=slingshot_ballistic,
        metrics=(
            REWARD,
            Metric("pigs", "pigs destroyed / episode", "episode", _episode("pigs_destroyed")),
            Metric("blocks", "blocks destroyed / episode", "episode", _episode("blocks_destroyed")),
            # One bird per step while birds are left, and the episode ends when they run out.
            Metric("birds_used", "birds used / episode", "episode", _episode("shots")),
            Metric("cleared", "levels cleared", "episode", _episode("final_cleared")),
        ),
        targets=(
            Target("beats_random_2x", "reward", 2.0, "random"),  # never negative here
            Target("half_of_scripted", "reward", 0.5, "scripted"),
            Target("matches_scripted", "reward", 1.0, "scripted"),
        ),
    )


def task(env_id: str) -> Task:
    """The metrics and targets of game ``env_id`` (the two slingshot games share theirs)."""
    if env_id in ("Slingshot2D-v0", "Slingshot2DBlocks-v0"):
        return _slingshot(env_id)
    return {"Pool2D-v0": _pool}[env_id]()


def play_episodes(
    env_id: str, env_kwargs: dict[str, Any], policy: Policy, episodes: int, seed: int
) -> dict[str, np.ndarray]:
    """Play the first episode of ``episodes`` worlds seeded ``seed``, ``seed + 1``, ...

    Returns per-episode arrays: ``return``, ``shots``, the episode sums of every numeric
    info key (``potted``, ``fouls``, ...) and, as ``final_<key>``, each key's value at the
    episode's last step (``final_cleared``, ``final_balls_left``, ...)."""
    import gymnasium as gym

    import impulse2d  # noqa: F401  (registers the env ids)

    venv = gym.make_vec(
        env_id, num_envs=episodes, vectorization_mode="vector_entry_point", **env_kwargs
    )
    obs, _ = venv.reset(seed=seed)
    record: dict[str, np.ndarray] = {
        "return": np.zeros(episodes),
        "shots": np.zeros(episodes, np.int64),
    }
    done = np.zeros(episodes, dtype=bool)
    while not done.all():
        obs, reward, terminated, truncated, info = venv.step(policy(obs))
        ended = np.asarray(terminated) | np.asarray(truncated)
        live = ~done
        record["return"][live] += reward[live]
        record["shots"][live] += 1
        for key, value in _step_info(info, ended).items():
            total = record.setdefault(key, np.zeros(episodes, value.dtype))
            total[live] += value[live]
            final = record.setdefault(f"final_{key}", np.zeros(episodes, value.dtype))
            final[live & ended] = value[live & ended]
        done |= ended
    venv.close()
    return record


def _step_info(info: dict[str, Any], ended: np.ndarray) -> dict[str, np.ndarray]:
    """Every env's info of this step, numeric keys only: the ones that just ended have
    theirs in ``final_info`` (the vector env has already reset them)."""
    final = info.get("final_info", {})
    out: dict[str, np.ndarray] = {}
    for key, value in info.items():
        if key.startswith("_") or key.startswith("final_"):
            continue
        value = np.asarray(value)
        if value.dtype.kind not in "biuf":
            continue
        if value.dtype == bool:
            value = value.astype(np.int64)
        if key in final:
            value = np.where(ended, np.asarray(final[key]).astype(value.dtype), value)
        out[key] = value
    for key, value in final.items():  # keys only the ending envs had (all ended this step)
        if key not in out and not key.startswith("_") and np.asarray(value).dtype.kind in "biuf":
            out[key] = np.asarray(value).astype(np.int64 if value.dtype == bool else value.dtype)
    return out


def summarize(task_: Task, record: dict[str, np.ndarray]) -> dict[str, dict[str, float]]:
    """The table row of one policy: ``{metric key: {"mean", "std"}}`` (``std`` is 0 for
    rates, which are one number)."""
    row: dict[str, dict[str, float]] = {}
    for metric in task_.metrics:
        value = metric.value(record)
        if metric.kind == "episode":
            row[metric.key] = {"mean": float(np.mean(value)), "std": float(np.std(value))}
        else:
            row[metric.key] = {"mean": float(value), "std": 0.0}
    return row
