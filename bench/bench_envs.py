"""Speed benchmark of the Gymnasium environments: shots per second to rest, in one run.

One *shot* is one env step: a cue stroke (or a launch) played until every body is at
rest or the step cap. The table gives shots/s (higher is better) for

* ``Pool2D-v0`` as a single env (``gym.make``, with its wrappers, as a user gets it) and
  as a vector env of 64, 256 and 1,024 worlds (``gym.make_vec(...,
  vectorization_mode="vector_entry_point")``: all worlds stepped in one batched engine).
  A vector step is one shot in every world and lasts until the slowest world is at rest,
  so shots/s = num_envs * vector steps / seconds.
* The same table and shot in pymunk (C Chipmunk2D, ``bench/pymunk_pool_env.py``; see its
  docstring for how every constant maps), in one process and in two worker processes
  each playing half the shots (the aggregate rate). Two pymunk models are timed: the
  *joints* model (rolling resistance and spin drag as Chipmunk joints, pockets as sensors,
  Chipmunk's own sleeping: the idiomatic pymunk way, all physics in C) is the reference
  for the ratio columns; the *numpy* model (the same friction applied by a vectorised
  Python pass over all balls every step, sleeping emulated) is shown for comparison.
  pymunk tables each start their next shot as soon as theirs has ended.
* ``Slingshot2D-v0`` as a single env and a vector env of 256 worlds (no pymunk peer).
  Its rows say "n/a (not installed)" if its module cannot be imported.

Every side plays random actions (impulse2d: ``action_space.sample()`` after
``action_space.seed``; pymunk: a seeded numpy generator, uniform in [-1, 1]) and starts a
new episode when one ends (a single env on termination or truncation; a vector env
autoresets, and its resets are inside the timing). Before timing, each side plays warm-up
shots on the same envs or tables, so first-call costs stay out and the shots timed are
mid-episode. ``steps/shot`` is the mean of ``info["physics_steps"]`` (pymunk: its own count
at the same dt) so the reader can see that the shots are alike; ``pots %`` is the share
of shots that potted an object ball, ``capped %`` of shots stopped by the step cap
before coming to rest. The ratio columns are impulse2d / pymunk (joints
model) in one and in two processes; the last line checks the issue's target, the
1,024-world vector env against pymunk in two processes.

Run ``python bench/bench_envs.py`` (about 3.5 minutes on 2 cores), ``--quick`` for a smoke
test (under a minute), ``--profile`` for a cProfile of one 1,024-world Pool2D shot.
The machine is shared: the header and footer print the load average, and a busy
spell during one row skews that row only.
"""

from __future__ import annotations

import argparse
import cProfile
import importlib
import io
import os
import platform
import pstats
import sys
import time
import traceback
from collections.abc import Callable
from typing import Any

import gymnasium as gym
import numpy as np
import pymunk

try:  # imported as part of the repo (``bench.bench_envs``) ...
    from bench import pymunk_pool_env as peer
    from bench import report
    from bench.report import fmt, ratio
except ImportError:  # ... or run as a script, with bench/ on sys.path
    import pymunk_pool_env as peer
    import report
    from report import fmt, ratio

POOL, SLING = "Pool2D-v0", "Slingshot2D-v0"
# Defaults sized for ~4 minutes on this 2-core machine: a 1,024-world Pool2D shot takes
# ~10 s (the slowest of 1,024 shots runs ~1,550 steps), a single-env shot ~0.25 s, a
# pymunk joints shot ~2.5 ms, a numpy-model shot ~12 ms.
SINGLE_SHOTS = 60
VECTOR_STEPS = {64: 6, 256: 4, 1024: 3}  # timed vector steps, after one warm-up step
PYMUNK_SHOTS = {"joints": 8000, "numpy": 1600}  # one process, ~20 s; two: twice as many
PYMUNK_TABLES = 32  # per process
SLING_SHOTS = 40
SLING_WORLDS = 256
SLING_STEPS = 3
QUICK = {
    "single_shots": 8,
    "worlds": [64],
    "vector_steps": 1,
    "pymunk_shots": {"joints": 1500, "numpy": 300},
    "sling_shots": 8,
    "sling_worlds": 64,
    "sling_steps": 1,
}

_SHOW_PROGRESS = True


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


def _stage(text: str) -> None:
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
def _make(env_id: str, num_envs: int | None = None) -> gym.Env | gym.vector.VectorEnv:
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
    return gym.make_vec(env_id, num_envs=num_envs, vectorization_mode="vector_entry_point")


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
    env_id: str, num_envs: int, steps: int, seed: int = 0, warmup: int = 1
) -> dict[str, Any]:
    """Shots/s of the vector env of ``num_envs`` worlds over ``steps`` vector steps (each
    one shot per world), after ``warmup`` untimed ones. ``slowest`` is the mean over the
    timed vector steps of the most physics steps any world took (what a vector step lasts).
    Raises :class:`NotInstalled` if the env's module cannot be imported."""
    env = _make(env_id, num_envs)
    _stage(f"{env_id} x {num_envs}: reset and {warmup} warm-up step(s)")
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
    return res


def profile_vector_shot(env_id: str = POOL, num_envs: int = 1024, top: int = 10) -> str:
    """cProfile of one vector step (one shot per world) after a warm-up step; the top
    functions by cumulative time."""
    env = _make(env_id, num_envs)
    env.reset(seed=0)
    env.action_space.seed(0)
    env.step(env.action_space.sample())
    actions = env.action_space.sample()
    profiler = cProfile.Profile()
    profiler.enable()
    env.step(actions)
    profiler.disable()
    out = io.StringIO()
    pstats.Stats(profiler, stream=out).sort_stats("cumulative").print_stats(top)
    return f"cProfile: one {env_id} vector step, {num_envs} worlds\n" + out.getvalue()


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


# -- table -------------------------------------------------------------------------------------
def _print_table(rows: list[tuple[str, ...]]) -> None:
    header = (
        "case",
        "worlds",
        "shots",
        "seconds",
        "shots/s",
        "steps/shot",
        "pots %",
        "capped %",
        "vs pm 1p",
        "vs pm 2p",
        "notes",
    )
    align = ("<", ">", ">", ">", ">", ">", ">", ">", ">", ">", "<")
    report.print_table(header, align, rows)


def _load() -> str:
    return ", ".join(f"{x:.2f}" for x in os.getloadavg())


def main(argv: list[str] | None = None) -> None:
    """Run every measurement and print the table."""
    global _SHOW_PROGRESS
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="small counts (under a minute)")
    parser.add_argument("--single-shots", type=int, help=f"single-env shots ({SINGLE_SHOTS})")
    parser.add_argument("--worlds", type=int, nargs="+", help="vector env sizes (64 256 1024)")
    parser.add_argument("--vector-steps", type=int, help="timed steps per vector env (6/4/3)")
    parser.add_argument("--pymunk-shots", type=int, help="joints-model shots in one process")
    parser.add_argument("--pymunk-tables", type=int, default=PYMUNK_TABLES, help="per process")
    parser.add_argument("--sling-shots", type=int, help=f"Slingshot single shots ({SLING_SHOTS})")
    parser.add_argument("--sling-worlds", type=int, help=f"Slingshot worlds ({SLING_WORLDS})")
    parser.add_argument("--sling-steps", type=int, help=f"Slingshot vector steps ({SLING_STEPS})")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--profile", action="store_true", help="cProfile a 1,024-world shot")
    parser.add_argument("--no-progress", action="store_true", help="no progress output")
    args = parser.parse_args(argv)
    _SHOW_PROGRESS = not args.no_progress

    if args.profile:
        print(profile_vector_shot(POOL, (args.worlds or [1024])[0]))
        return

    quick = QUICK if args.quick else {}
    single_shots = args.single_shots or quick.get("single_shots", SINGLE_SHOTS)
    worlds = args.worlds or quick.get("worlds", list(VECTOR_STEPS))
    vec_steps = {
        n: args.vector_steps or quick.get("vector_steps", VECTOR_STEPS.get(n, 3)) for n in worlds
    }
    pm_shots = dict(quick.get("pymunk_shots", PYMUNK_SHOTS))
    if args.pymunk_shots:  # the numpy model is ~5x slower: keep its share of the time
        pm_shots = {"joints": args.pymunk_shots, "numpy": max(1, args.pymunk_shots // 5)}
    sling_shots = args.sling_shots or quick.get("sling_shots", SLING_SHOTS)
    sling_worlds = args.sling_worlds or quick.get("sling_worlds", SLING_WORLDS)
    sling_steps = args.sling_steps or quick.get("sling_steps", SLING_STEPS)
    tables, seed = args.pymunk_tables, args.seed

    t_start = time.perf_counter()
    print("Gymnasium envs: shots per second to rest" + (" (--quick)" if args.quick else ""))
    print(
        f"python {platform.python_version()}, numpy {np.__version__}, gymnasium "
        f"{gym.__version__}, pymunk {pymunk.version} (Chipmunk {pymunk.chipmunk_version[:5]}), "
        f"{os.cpu_count()} CPUs, load average {_load()} at start"
    )
    print(report.source_version())
    print(
        f"{POOL}: 16 balls, dt 1/120 s, 2 substeps, shot until all asleep (0.1 s below "
        "0.01 m/s) or 20 s; episodes of 30 shots; random actions, seed "
        f"{seed}; single env {single_shots} shots after 3 warm-up; vector envs "
        + ", ".join(f"{n} worlds {k}" for n, k in vec_steps.items())
        + " timed vector steps after 1 warm-up step"
    )
    print(
        f"pymunk: same table and shot, one Space per table, 10 iterations, 1 step per dt; "
        f"{tables} tables per process, 2 warm-up shots per table; 2 processes: spawned, "
        "half the shots each, aggregate rate from a common start barrier"
    )

    rows: list[tuple[str, ...]] = []
    errors = 0
    pm: dict[tuple[str, int], dict] = {}
    for model in peer.MODELS:
        for procs in (1, 2):
            _stage(f"pymunk {model} model, {procs} process(es)")
            pm[(model, procs)] = measure_pymunk(model, procs, pm_shots[model] * procs, tables, seed)
    ref1, ref2 = pm[("joints", 1)]["shots_per_s"], pm[("joints", 2)]["shots_per_s"]
    num1, num2 = pm[("numpy", 1)]["shots_per_s"], pm[("numpy", 2)]["shots_per_s"]

    def add(case: str, n: int | str, res: dict | None, notes: str, ratios: bool = True) -> None:
        """One table row; ``res`` None for an env that could not be measured."""
        if res is None:
            rows.append((case, str(n), "-", "-", notes, *["-"] * 3, "—", "—", ""))
            return
        rate = res["shots_per_s"]
        pct = [
            None if res[k] is None else f"{100 * res[k]:.1f}" for k in ("pot_fraction", "capped")
        ]
        rows.append(
            (
                case,
                str(n),
                str(res["shots"]),
                f"{res['seconds']:.1f}",
                fmt(rate),
                fmt(res["mean_steps"]),
                *[p or "-" for p in pct],
                ratio(rate, ref1) if ratios else "—",
                ratio(rate, ref2) if ratios else "—",
                notes,
            )
        )

    imp: dict[int, dict] = {}
    _stage(f"{POOL} single env, {single_shots} shots")
    imp[1] = measure_single(POOL, single_shots, seed)
    add(
        f"{POOL} single env",
        1,
        imp[1],
        f"gym.make with its wrappers; vs numpy-model peer x{imp[1]['shots_per_s'] / num1:.3g} (1p)",
    )
    for n in worlds:
        steps = vec_steps[n]
        imp[n] = res = measure_vector(POOL, n, steps, seed)
        add(
            f"{POOL} vector env",
            n,
            res,
            f"{steps} vector step(s), slowest world {res['slowest']:.0f} steps a vector step; vs "
            f"numpy-model peer x{res['shots_per_s'] / num1:.3g} (1p), "
            f"x{res['shots_per_s'] / num2:.3g} (2p)",
        )
    for model in peer.MODELS:
        for procs in (1, 2):
            res = dict(pm[(model, procs)])
            notes = "ratio reference" if model == "joints" else "Python friction pass a step"
            if res["python_share"] is not None:
                notes += f", {100 * res['python_share']:.0f} % of time outside space.step"
            if procs > 1:
                notes += "; per process " + ", ".join(f"{r:.0f}" for r in res["per_process"])
            notes += f"; balls through a cushion: {res['escaped']}"
            res["capped"] /= res["shots"]
            case = f"pymunk pool, {model} model, {procs} proc{'s' if procs > 1 else ''}"
            add(case, f"{tables * procs} tables", res, notes, ratios=False)

    for n, label in ((1, "single env"), (sling_worlds, "vector env")):
        case = f"{SLING} {label}"
        _stage(case)
        try:
            if n == 1:
                res = measure_single(SLING, sling_shots, seed)
                note = "gym.make with its wrappers"
            else:
                res = measure_vector(SLING, n, sling_steps, seed)
                note = f"{sling_steps} vector step(s), slowest world {fmt(res['slowest'])} steps"
        except NotInstalled as error:
            add(case, n, None, "n/a (not installed)")
            print(f"    {SLING} not available: {error}", file=sys.stderr)
            continue
        except Exception as error:  # the env is being written: report, do not lose the table
            traceback.print_exc()
            errors += 1
            add(case, n, None, f"error: {type(error).__name__}"[:40])
            continue
        add(case, n, res, note + " (no pymunk peer)", ratios=False)

    print()
    _print_table(rows)
    print()
    print(
        "steps/shot: mean physics steps per shot at dt 1/120 s (Slingshot 1/60); pots %: shots "
        "that potted an object ball; capped %: shots stopped by the step cap (Pool2D 20 s) "
        "before coming to rest; vs pm: impulse2d / pymunk joints model (1 or 2 processes)"
    )
    big = max(worlds)
    rate = imp[big]["shots_per_s"]
    verdict = "ok" if rate >= ref2 else "MISS"
    print(
        f"target: {POOL} x {big} >= pymunk in 2 processes: {fmt(rate)} vs {fmt(ref2)} "
        f"shots/s (joints model), x{rate / ref2:.3g}: {verdict}; against the numpy model "
        f"{fmt(num2)} shots/s, x{rate / num2:.3g}: {'ok' if rate >= num2 else 'MISS'}"
        + ("" if big == 1024 else " (the target is set for 1,024 worlds)")
    )
    print(f"load average {_load()} at end; total wall time {time.perf_counter() - t_start:.0f} s")
    if errors:
        sys.exit(1)


if __name__ == "__main__":
    main()
