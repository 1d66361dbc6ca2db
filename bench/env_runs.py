"""The measuring side of the env benchmark (``bench/bench_envs.py``).

Shots per second of the impulse2d Gymnasium envs (a single env from ``gym.make``, a vector
env from ``gym.make_vec(..., vectorization_mode="vector_entry_point")``) and of the pymunk
peer (``bench/pymunk_pool_env.py``), with progress on stderr; and ``time_split``, the
``--profile`` report: how an env step's time divides between the compiled run of the shot
(``World.run_until_rest``, and inside it the runner's compiled call) and the env's Python
around it (the launch, scoring, observations and, in a vector env, the autoresets).
"""

from __future__ import annotations

import importlib
import sys
import time
from collections.abc import Callable
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium.vector import AutoresetMode

try:  # imported as part of the repo (``bench.env_runs``) ...
    from bench import pymunk_pool_env as peer
except ImportError:  # ... or run as a script, with bench/ on sys.path
    import pymunk_pool_env as peer

_SHOW_PROGRESS = True


def set_progress(show: bool) -> None:
    """Show progress (bars and stage lines on stderr) or not: ``--no-progress``."""
    global _SHOW_PROGRESS
    _SHOW_PROGRESS = show


class NotInstalled(Exception):
    """The env's module cannot be imported (the Slingshot env may not exist yet)."""


# -- progress ----------------------------------------------------------------------------------
def _bar(total: int, desc: str) -> Any:
    """A tqdm bar on stderr (none when stderr is not a terminal, or tqdm is missing)."""
    if _SHOW_PROGRESS:
        try:
            from tqdm import tqdm
        except ImportError:
            pass
        else:
            return tqdm(total=total, desc=desc, leave=False, disable=None)
    return None


def stage(text: str) -> None:
    """Say what is running (stderr, so the table on stdout stays clean)."""
    if _SHOW_PROGRESS:
        print(f"... {text}", file=sys.stderr, flush=True)


def _run_with_bar(total: int, desc: str, run: Callable[[Callable[[int], None]], Any]) -> Any:
    bar = _bar(total, desc)
    try:
        return run(bar.update if bar is not None else lambda n: None)
    finally:
        if bar is not None:
            bar.close()


# -- impulse2d envs ----------------------------------------------------------------------------
def _make(
    env_id: str, num_envs: int | None = None, **options: Any
) -> gym.Env | gym.vector.VectorEnv:
    """``gym.make`` or the batched ``gym.make_vec``; :class:`NotInstalled` if the entry
    point's module cannot be imported or lacks the class (an error inside the env's
    constructor is not hidden)."""
    spec = gym.spec(env_id)
    entry = spec.entry_point if num_envs is None else spec.vector_entry_point
    if isinstance(entry, str):
        module_name, _, attr = entry.partition(":")
        try:
            module = importlib.import_module(module_name)
        except ImportError as error:
            raise NotInstalled(str(error)) from error
        if not hasattr(module, attr):
            raise NotInstalled(f"{module_name} has no {attr}")
    if num_envs is None:
        return gym.make(env_id)
    # Same-step autoreset: every vector step is one shot per world (NEXT_STEP spends a
    # step on each reset), as SB3 training runs it.
    return gym.make_vec(
        env_id, num_envs=num_envs, vectorization_mode="vector_entry_point",
        autoreset_mode=AutoresetMode.SAME_STEP, **options,
    )  # fmt: skip


def _summary(env: Any, shots: int, seconds: float, steps: list, pots: list) -> dict[str, Any]:
    game = getattr(env.unwrapped, "game", None)  # the shot game: its step cap, if any
    cap = getattr(game, "max_shot_steps", None)
    return {
        "shots": shots,
        "seconds": seconds,
        "shots_per_s": shots / seconds,
        "mean_steps": float(np.mean(steps)) if steps else None,
        "pot_fraction": float(np.mean(pots)) if pots else None,
        "capped": float(np.mean(np.array(steps) >= cap)) if steps and cap else None,
    }


def measure_single(env_id: str, shots: int, seed: int = 0, warmup: int = 3) -> dict[str, Any]:
    """Shots/s of ``gym.make(env_id)`` with random actions, ``warmup`` untimed shots first.
    Raises :class:`NotInstalled` if the env's module cannot be imported."""
    env = _make(env_id)
    env.reset(seed=seed)
    env.action_space.seed(seed)
    steps: list[int] = []
    pots: list[bool] = []

    def play(n: int, update: Callable[[int], None]) -> None:
        for _ in range(n):
            _, _, terminated, truncated, info = env.step(env.action_space.sample())
            if "physics_steps" in info:
                steps.append(int(info["physics_steps"]))
            if "potted" in info:
                pots.append(int(info["potted"]) > 0)
            if terminated or truncated:
                env.reset()
            update(1)

    play(warmup, lambda n: None)
    steps.clear()
    pots.clear()

    def timed(update: Callable[[int], None]) -> float:
        t0 = time.perf_counter()
        play(shots, update)
        return time.perf_counter() - t0

    seconds = _run_with_bar(shots, f"{env_id} single env", timed)
    res = _summary(env, shots, seconds, steps, pots)
    env.close()
    return res


def _per_env(info: dict[str, Any], key: str) -> np.ndarray | None:
    """``info[key]`` for every env of a vector step: the envs that ended an episode have
    theirs in ``final_info`` (Gymnasium's same-step autoreset layout)."""
    if key not in info and key not in info.get("final_info", {}):
        return None
    values = None
    if key in info:
        values = np.where(info[f"_{key}"], info[key], 0)
    final = info.get("final_info", {})
    if key in final:
        extra = np.where(final[f"_{key}"], final[key], 0)
        values = extra if values is None else np.where(final[f"_{key}"], extra, values)
    return values


def measure_vector(
    env_id: str, num_envs: int, steps: int, seed: int = 0, warmup: int = 1, **options: Any
) -> dict[str, Any]:
    """Shots/s of the vector env of ``num_envs`` worlds over ``steps`` vector steps (each
    one shot per world), after ``warmup`` untimed ones; ``options`` go to the env
    (``obs_type="pixels"``). ``slowest`` is the mean over the timed vector steps of the
    most physics steps any world took (what a vector step lasts). Raises
    :class:`NotInstalled` if the env's module cannot be imported."""
    env = _make(env_id, num_envs, **options)
    stage(f"{env_id} x {num_envs}: reset and {warmup} warm-up step(s)")
    env.reset(seed=seed)
    env.action_space.seed(seed)
    for _ in range(warmup):
        env.step(env.action_space.sample())
    shot_steps: list[np.ndarray] = []
    pots: list[np.ndarray] = []

    def timed(update: Callable[[int], None]) -> float:
        seconds = 0.0
        for _ in range(steps):
            actions = env.action_space.sample()
            t0 = time.perf_counter()
            *_, info = env.step(actions)
            seconds += time.perf_counter() - t0
            for out, key in ((shot_steps, "physics_steps"), (pots, "potted")):
                values = _per_env(info, key)
                if values is not None:
                    out.append(values)
            update(1)
        return seconds

    seconds = _run_with_bar(steps, f"{env_id} x {num_envs}", timed)
    env.close()
    res = _summary(
        env,
        num_envs * steps,
        seconds,
        list(np.concatenate(shot_steps)) if shot_steps else [],
        list(np.concatenate(pots) > 0) if pots else [],
    )
    res["slowest"] = float(np.mean([s.max() for s in shot_steps])) if shot_steps else None
    res["threads"] = env.unwrapped.game.world.threads
    return res


# -- pymunk ------------------------------------------------------------------------------------
def measure_pymunk(model: str, processes: int, shots: int, tables: int, seed: int) -> dict:
    desc = f"pymunk {model}, {processes} process(es)"
    if processes == 1:
        res = _run_with_bar(
            shots,
            desc,
            lambda update: peer.play_shots(shots, tables, seed, model=model, progress=update),
        )
    else:
        res = _run_with_bar(
            shots,
            desc,
            lambda update: peer.play_shots_parallel(
                shots, processes, tables, seed, model=model, progress=update
            ),
        )
    peer.check_result(res)
    return res


# -- where an env step's time goes (--profile) ---------------------------------------------------
def _clocked(world: Any) -> dict[str, float]:
    """Put clocks around ``world.run_until_rest`` and around its runner's compiled call
    (``Runner._call``, the one call into ``pipeline``); returns the seconds they add up."""
    spent = {"run_until_rest": 0.0, "compiled": 0.0}

    def timed(function: Callable[..., Any], key: str) -> Callable[..., Any]:
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            t0 = time.perf_counter()
            try:
                return function(*args, **kwargs)
            finally:
                spent[key] += time.perf_counter() - t0

        return wrapper

    world.run_until_rest = timed(world.run_until_rest, "run_until_rest")
    world._runner._call = timed(world._runner._call, "compiled")
    return spent


def time_split(
    env_id: str, num_envs: int | None, moves: int, seed: int = 0, warmup: int = 1
) -> dict[str, Any]:
    """Play ``moves`` env steps (a single env with ``num_envs`` None, else vector steps)
    after ``warmup`` untimed ones, with random actions, and split the time of the env
    steps (a single env's resets included) between the compiled run of the shots
    (``World.run_until_rest``; ``compiled``: the runner's compiled calls inside it) and
    the env's Python around it. Also counts the physics world-steps taken."""
    env = _make(env_id, num_envs)
    env.reset(seed=seed)
    env.action_space.seed(seed)
    single = num_envs is None

    def move() -> int:
        *_, terminated, truncated, info = env.step(env.action_space.sample())
        if single:
            if terminated or truncated:
                env.reset()
            return int(info.get("physics_steps", 0))
        steps = _per_env(info, "physics_steps")
        return 0 if steps is None else int(steps.sum())

    for _ in range(warmup):
        move()
    spent = _clocked(env.unwrapped.game.world)
    seconds, world_steps = 0.0, 0
    for _ in range(moves):
        t0 = time.perf_counter()
        world_steps += move()
        seconds += time.perf_counter() - t0
    env.close()
    return {
        "shots": moves * (num_envs or 1),
        "seconds": seconds,
        "world_steps": world_steps,
        "threads": 1 if single else env.unwrapped.game.world.threads,
        **spent,
    }
