"""Speed benchmark of the Gymnasium environments: shots per second to rest, in one run.

One *shot* is one env step: a cue stroke (or a launch) played until every body is at
rest or the step cap, in compiled code (``World.run_until_rest``: one call for the whole
shot, a world at rest costing nothing while the others go on). The table gives shots/s
(higher is better) for

* ``Pool2D-v0`` as a single env (``gym.make``, with its wrappers, as a user gets it; one
  world, one thread) and as a vector env of 64, 256 and 1,024 worlds (``gym.make_vec(...,
  vectorization_mode="vector_entry_point")``: all worlds stepped in one batched engine, on
  ``World.threads`` threads, by default every core numba sees; the header prints how
  many). A vector step is one shot in every world and lasts until the slowest world is at
  rest, so shots/s = num_envs * vector steps / seconds.
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
before coming to rest. The ratio columns are impulse2d / pymunk (joints model) in one and
in two processes. The lines under the table check the issue's targets: the single
Pool2D env at least 0.5x pymunk in one process, the 1,024-world Pool2D vector env at least
1.5x pymunk in two processes, and the 256-world Slingshot vector env at least 505 shots/s
(5x the 101 of the numpy engine).

Run ``python bench/bench_envs.py`` (about 1.5 minutes on 2 cores), ``--quick`` for a smoke
test (under half a minute). ``--profile`` prints instead where an env step's time goes
(``env_runs.time_split``): perf_counter around ``World.run_until_rest`` and around the
runner's compiled call inside it, against the whole ``env.step``, for the single and
vector envs of both games (cProfile would see the compiled run as one opaque call).
The machine is shared: the header and footer print the load average, and a busy
spell during one row skews that row only.
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import time
import traceback
from dataclasses import dataclass

import gymnasium as gym
import numba
import numpy as np
import pymunk

import impulse2d as p2
from impulse2d.core.runner import available_threads

try:  # imported as part of the repo (``bench.bench_envs``) ...
    from bench import env_runs, report
    from bench import pymunk_pool_env as peer
    from bench.env_runs import NotInstalled, stage
    from bench.report import fmt, ratio
except ImportError:  # ... or run as a script, with bench/ on sys.path
    import env_runs
    import pymunk_pool_env as peer
    import report
    from env_runs import NotInstalled, stage
    from report import fmt, ratio

POOL, SLING = "Pool2D-v0", "Slingshot2D-v0"
# Defaults sized for ~1.5 minutes on this 2-core machine: a single-env Pool2D shot takes
# ~2.4 ms, a 1,024-world vector step ~0.65 s (the slowest of 1,024 shots runs ~1,550
# steps), a pymunk joints shot ~1.4 ms, a numpy-model shot ~5 ms, a single Slingshot
# launch ~1.7 ms, a 256-world Slingshot vector step ~0.26 s.
SINGLE_SHOTS = 2000
VECTOR_STEPS = {64: 60, 256: 24, 1024: 10}  # timed vector steps, after one warm-up step
PYMUNK_SHOTS = {"joints": 8000, "numpy": 1600}  # 1 process: ~12 and ~8 s; 2: twice as many
PYMUNK_TABLES = 32  # per process
SLING_SHOTS = 2000
SLING_WORLDS = 256
SLING_STEPS = 20
QUICK = {
    "single_shots": 100,
    "worlds": [64],
    "vector_steps": 3,
    "pymunk_shots": {"joints": 1500, "numpy": 300},
    "sling_shots": 100,
    "sling_worlds": 64,
    "sling_steps": 2,
}
# The targets.
SINGLE_TARGET = 0.5  # Pool2D single env / pymunk joints model in 1 process, at least
VECTOR_TARGET = 1.5  # Pool2D vector env of 1,024 worlds / pymunk joints in 2 processes
VECTOR_TARGET_WORLDS = 1024
SLING_TARGET = 505.0  # Slingshot2D vector env of 256 worlds, shots/s (5x the old 101)
SLING_TARGET_WORLDS = 256

Row = tuple[str, ...]


@dataclass(frozen=True)
class Config:
    """What this run measures, from the command line."""

    quick: bool
    single_shots: int
    vec_steps: dict[int, int]  # timed vector steps by world count
    pm_shots: dict[str, int]  # pymunk shots in one process, by model
    tables: int  # pymunk tables per process
    sling_shots: int
    sling_worlds: int
    sling_steps: int
    seed: int
    profile: bool

    @property
    def worlds(self) -> list[int]:
        return list(self.vec_steps)


# -- setup ---------------------------------------------------------------------------------------
def _parse_args(argv: list[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="small counts (a smoke test)")
    parser.add_argument("--single-shots", type=int, help=f"single-env shots ({SINGLE_SHOTS})")
    parser.add_argument("--worlds", type=int, nargs="+", help="vector env sizes (64 256 1024)")
    parser.add_argument("--vector-steps", type=int, help="timed steps per vector env (60/24/10)")
    parser.add_argument("--pymunk-shots", type=int, help="joints-model shots in one process")
    parser.add_argument("--pymunk-tables", type=int, default=PYMUNK_TABLES, help="per process")
    parser.add_argument("--sling-shots", type=int, help=f"Slingshot single shots ({SLING_SHOTS})")
    parser.add_argument("--sling-worlds", type=int, help=f"Slingshot worlds ({SLING_WORLDS})")
    parser.add_argument("--sling-steps", type=int, help=f"Slingshot vector steps ({SLING_STEPS})")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument(
        "--profile", action="store_true", help="where an env step's time goes, and exit"
    )
    parser.add_argument("--no-progress", action="store_true", help="no progress output")
    return parser.parse_args(argv)


def _config(args: argparse.Namespace) -> Config:
    quick = QUICK if args.quick else {}
    worlds = args.worlds or quick.get("worlds", list(VECTOR_STEPS))
    vec_steps = {
        n: args.vector_steps or quick.get("vector_steps", VECTOR_STEPS.get(n, 10)) for n in worlds
    }
    pm_shots = dict(quick.get("pymunk_shots", PYMUNK_SHOTS))
    if args.pymunk_shots:  # the numpy model is ~5x slower: keep its share of the time
        pm_shots = {"joints": args.pymunk_shots, "numpy": max(1, args.pymunk_shots // 5)}
    return Config(
        quick=args.quick,
        single_shots=args.single_shots or quick.get("single_shots", SINGLE_SHOTS),
        vec_steps=vec_steps,
        pm_shots=pm_shots,
        tables=args.pymunk_tables,
        sling_shots=args.sling_shots or quick.get("sling_shots", SLING_SHOTS),
        sling_worlds=args.sling_worlds or quick.get("sling_worlds", SLING_WORLDS),
        sling_steps=args.sling_steps or quick.get("sling_steps", SLING_STEPS),
        seed=args.seed,
        profile=args.profile,
    )


def _load() -> str:
    return ", ".join(f"{x:.2f}" for x in os.getloadavg())


def _threads_line() -> str:
    return (
        f"threads: impulse2d vector envs step their batch on {p2.World().threads} "
        f"(World.threads, its default: every core numba sees; impulse2d.core.runner."
        f"available_threads() = {available_threads()}: Python threads, each stepping "
        f"chunks of the batch in compiled code); a single env is one world on one thread"
    )


def _print_header(cfg: Config) -> None:
    print("Gymnasium envs: shots per second to rest" + (" (--quick)" if cfg.quick else ""))
    print(
        f"python {platform.python_version()}, numpy {np.__version__}, numba {numba.__version__}, "
        f"gymnasium {gym.__version__}, pymunk {pymunk.version} (Chipmunk "
        f"{pymunk.chipmunk_version[:5]}), {os.cpu_count()} CPUs, load average {_load()} at start"
    )
    print(report.source_version())
    print(_threads_line())
    print(
        f"{POOL}: 16 balls, dt 1/120 s, 2 substeps, shot until all asleep (0.1 s below "
        "0.01 m/s) or 20 s; episodes of 30 shots; random actions, seed "
        f"{cfg.seed}; single env {cfg.single_shots} shots after 3 warm-up; vector envs "
        + ", ".join(f"{n} worlds {k}" for n, k in cfg.vec_steps.items())
        + " timed vector steps after 1 warm-up step"
    )
    print(
        f"pymunk: same table and shot, one Space per table, 10 iterations, 1 step per dt; "
        f"{cfg.tables} tables per process, 2 warm-up shots per table; 2 processes: spawned, "
        "half the shots each, aggregate rate from a common start barrier"
    )
    print(
        f"{SLING}: dt 1/60 s, 4 substeps, random levels; single env {cfg.sling_shots} shots "
        f"after 3 warm-up; vector env {cfg.sling_worlds} worlds, {cfg.sling_steps} timed "
        "vector steps after 1 warm-up step"
    )


# -- rows ----------------------------------------------------------------------------------------
def _row(case: str, n: int | str, res: dict | None, notes: str, refs: tuple | None) -> Row:
    """One table row; ``res`` None for an env that could not be measured; ``refs`` the
    pymunk rates (1 and 2 processes) for the ratio columns, None for no ratios."""
    if res is None:
        return (case, str(n), "-", "-", notes, *["-"] * 3, "—", "—", "")
    rate = res["shots_per_s"]
    pct = [None if res[k] is None else f"{100 * res[k]:.1f}" for k in ("pot_fraction", "capped")]
    return (
        case,
        str(n),
        str(res["shots"]),
        fmt(res["seconds"]),
        fmt(rate),
        fmt(res["mean_steps"]),
        *[p or "-" for p in pct],
        ratio(rate, refs[0]) if refs else "—",
        ratio(rate, refs[1]) if refs else "—",
        notes,
    )


def _measure_peers(cfg: Config) -> dict[tuple[str, int], dict]:
    pm: dict[tuple[str, int], dict] = {}
    for model in peer.MODELS:
        for procs in (1, 2):
            stage(f"pymunk {model} model, {procs} process(es)")
            pm[(model, procs)] = env_runs.measure_pymunk(
                model, procs, cfg.pm_shots[model] * procs, cfg.tables, cfg.seed
            )
    return pm


def _peer_rows(cfg: Config, pm: dict[tuple[str, int], dict]) -> list[Row]:
    rows = []
    for (model, procs), run in pm.items():
        res = dict(run)
        notes = "ratio reference" if model == "joints" else "Python friction pass a step"
        if res["python_share"] is not None:
            notes += f", {100 * res['python_share']:.0f} % of time outside space.step"
        if procs > 1:
            notes += "; per process " + ", ".join(f"{r:.0f}" for r in res["per_process"])
        notes += f"; balls through a cushion: {res['escaped']}"
        res["capped"] /= res["shots"]
        case = f"pymunk pool, {model} model, {procs} proc{'s' if procs > 1 else ''}"
        rows.append(_row(case, f"{cfg.tables * procs} tables", res, notes, None))
    return rows


def _pool_rows(cfg: Config, pm: dict[tuple[str, int], dict]) -> tuple[list[Row], dict]:
    """Pool2D single env and vector envs; returns the rows and the runs by world count."""
    refs = (pm[("joints", 1)]["shots_per_s"], pm[("joints", 2)]["shots_per_s"])
    num1, num2 = pm[("numpy", 1)]["shots_per_s"], pm[("numpy", 2)]["shots_per_s"]
    imp: dict[int, dict] = {}
    stage(f"{POOL} single env, {cfg.single_shots} shots")
    imp[1] = res = env_runs.measure_single(POOL, cfg.single_shots, cfg.seed)
    rows = [
        _row(
            f"{POOL} single env",
            1,
            res,
            f"gym.make with its wrappers; vs numpy-model peer x{res['shots_per_s'] / num1:.3g} "
            "(1p)",
            refs,
        )
    ]
    for n, steps in cfg.vec_steps.items():
        imp[n] = res = env_runs.measure_vector(POOL, n, steps, cfg.seed)
        notes = (
            f"{res['threads']} threads; {steps} vector steps, slowest world "
            f"{res['slowest']:.0f} steps a vector step; vs numpy-model peer "
            f"x{res['shots_per_s'] / num1:.3g} (1p), x{res['shots_per_s'] / num2:.3g} (2p)"
        )
        rows.append(_row(f"{POOL} vector env", n, res, notes, refs))
    n, steps = max(cfg.vec_steps), cfg.vec_steps[max(cfg.vec_steps)]
    pixels = env_runs.measure_vector(POOL, n, steps, cfg.seed, obs_type="pixels")
    ratio = pixels["shots_per_s"] / imp[n]["shots_per_s"]
    notes = (
        f"obs_type='pixels' (84x84 RGB, every table's frame each step): x{ratio:.2f} the "
        f"state env's shots/s above (target >= 0.5: {'ok' if ratio >= 0.5 else 'MISS'})"
    )
    rows.append(_row(f"{POOL} vector env, pixels", n, pixels, notes, refs))
    return rows, imp


def _sling_rows(cfg: Config) -> tuple[list[Row], dict[int, dict], int]:
    """Slingshot2D single and vector env; returns the rows, the runs and the errors."""
    rows, runs, errors = [], {}, 0
    for n, label in ((1, "single env"), (cfg.sling_worlds, "vector env")):
        case = f"{SLING} {label}"
        stage(case)
        try:
            if n == 1:
                res = env_runs.measure_single(SLING, cfg.sling_shots, cfg.seed)
                note = "gym.make with its wrappers"
            else:
                res = env_runs.measure_vector(SLING, n, cfg.sling_steps, cfg.seed)
                note = (
                    f"{res['threads']} threads; {cfg.sling_steps} vector steps, slowest world "
                    f"{fmt(res['slowest'])} steps"
                )
        except NotInstalled as error:
            rows.append(_row(case, n, None, "n/a (not installed)", None))
            print(f"    {SLING} not available: {error}", file=sys.stderr)
            continue
        except Exception as error:  # an env being written: report, do not lose the table
            traceback.print_exc()
            errors += 1
            rows.append(_row(case, n, None, f"error: {type(error).__name__}"[:40], None))
            continue
        runs[n] = res
        rows.append(_row(case, n, res, note + " (no pymunk peer)", None))
    return rows, runs, errors


# -- table and targets ---------------------------------------------------------------------------
def _print_table(rows: list[Row]) -> None:
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


def _verdict(value: float, target: float) -> str:
    return "ok" if value >= target else "MISS"


def _print_targets(imp: dict[int, dict], sling: dict[int, dict], pm: dict) -> None:
    """The issue's three env targets, each ok or MISS (or not measured in this run)."""
    ref1, ref2 = pm[("joints", 1)]["shots_per_s"], pm[("joints", 2)]["shots_per_s"]
    num2 = pm[("numpy", 2)]["shots_per_s"]
    rate = imp[1]["shots_per_s"]
    print(
        f"target: {POOL} single env >= {SINGLE_TARGET:g}x pymunk in 1 process: {fmt(rate)} vs "
        f"{fmt(ref1)} shots/s (joints model), x{rate / ref1:.3g}: "
        f"{_verdict(rate / ref1, SINGLE_TARGET)}"
    )
    n = VECTOR_TARGET_WORLDS
    if n in imp:
        rate, threads = imp[n]["shots_per_s"], imp[n]["threads"]
        print(
            f"target: {POOL} vector env x {n:,} ({threads} threads) >= {VECTOR_TARGET:g}x pymunk "
            f"in 2 processes: {fmt(rate)} vs {fmt(ref2)} shots/s (joints model), "
            f"x{rate / ref2:.3g}: {_verdict(rate / ref2, VECTOR_TARGET)}; against the numpy "
            f"model {fmt(num2)} shots/s, x{rate / num2:.3g}"
        )
    else:
        print(f"target: {POOL} vector env x {n:,}: not measured (--worlds without {n})")
    n = SLING_TARGET_WORLDS
    if n in sling:
        rate = sling[n]["shots_per_s"]
        print(
            f"target: {SLING} vector env x {n} >= {SLING_TARGET:g} shots/s (5x the numpy "
            f"engine's 101): {fmt(rate)} shots/s, x{rate / 101:.3g} the old: "
            f"{_verdict(rate, SLING_TARGET)}"
        )
    else:
        print(f"target: {SLING} vector env x {n}: not measured (--sling-worlds {n})")


# -- --profile -----------------------------------------------------------------------------------
def _print_profile(cfg: Config) -> None:
    """Where an env step's time goes: the compiled shot against the env's Python."""
    print(f"Gymnasium envs: where an env step's time goes; load average {_load()} at start")
    print(report.source_version())
    print(_threads_line())
    big = max(cfg.worlds)
    cases = [
        (POOL, None, min(cfg.single_shots, 500)),
        (POOL, big, min(cfg.vec_steps[big], 5)),
        (SLING, None, min(cfg.sling_shots, 500)),
        (SLING, cfg.sling_worlds, min(cfg.sling_steps, 5)),
    ]
    rows = []
    for env_id, n, moves in cases:
        label = f"{env_id} {'single' if n is None else 'vector'} env"
        stage(f"{label}, {moves} env steps with clocks")
        r = env_runs.time_split(env_id, n, moves, cfg.seed)
        python = r["seconds"] - r["run_until_rest"]
        rows.append(
            (
                label,
                str(n or 1),
                str(r["threads"]),
                str(r["shots"]),
                fmt(r["seconds"]),
                f"{100 * r['compiled'] / r['seconds']:.1f}",
                f"{100 * (r['run_until_rest'] - r['compiled']) / r['seconds']:.1f}",
                f"{100 * python / r['seconds']:.1f}",
                fmt(1e6 * python / r["shots"]),
                fmt(1e6 * r["compiled"] / max(r["world_steps"], 1)),
            )
        )
    header = ("case", "worlds", "threads", "shots", "env.step s", "compiled %",
              "run_until_rest Python %", "env Python %", "env Python us/shot",
              "compiled us/world-step")  # fmt: skip
    print()
    report.print_table(header, ("<", *[">"] * 9), rows)
    print(
        "\ncompiled: the runner's compiled calls (pipeline.advance, one a chunk of worlds) inside "
        "World.run_until_rest; run_until_rest Python: the rest of that method; env Python: "
        "the env step outside it (launch, scoring, observation, info; a vector env's "
        "autoresets, a single env's resets); compiled us/world-step: wall time over the "
        "physics steps the worlds took (a world at rest takes none)"
    )
    print(f"load average {_load()} at end")


def main(argv: list[str] | None = None) -> None:
    """Run every measurement and print the table."""
    args = _parse_args(argv)
    env_runs.set_progress(not args.no_progress)
    cfg = _config(args)
    if cfg.profile:
        _print_profile(cfg)
        return
    t_start = time.perf_counter()
    _print_header(cfg)
    pm = _measure_peers(cfg)
    rows, imp = _pool_rows(cfg, pm)
    rows += _peer_rows(cfg, pm)
    sling_rows, sling, errors = _sling_rows(cfg)
    rows += sling_rows
    print()
    _print_table(rows)
    print()
    print(
        "steps/shot: mean physics steps per shot at dt 1/120 s (Slingshot 1/60); pots %: shots "
        "that potted an object ball; capped %: shots stopped by the step cap (Pool2D 20 s) "
        "before coming to rest; vs pm: impulse2d / pymunk joints model (1 or 2 processes)"
    )
    _print_targets(imp, sling, pm)
    print(f"load average {_load()} at end; total wall time {time.perf_counter() - t_start:.0f} s")
    if errors:
        sys.exit(1)


if __name__ == "__main__":
    main()
