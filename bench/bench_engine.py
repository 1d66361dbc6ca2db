"""Speed benchmark: impulse2d against pymunk (C Chipmunk2D) and Box2D v3 on the shared scenes.

The scenes come from ``bench/scenes.py``, the pymunk side from ``bench/pymunk_peer.py``, the
Box2D v3 side (``pyb2d3``) from ``bench/box2d_peer.py``, the impulse2d side from
``bench/engine_runs.py`` and the table's sections, which time the engines, from
``bench/engine_rows.py``; this module runs them in one process and prints one table with
the engines side by side and the ratios impulse2d / pymunk and impulse2d / Box2D (so for
a rate higher is better and for a time lower is better). Box2D runs the pyramids, the rain
and its own ``large_pyramid`` benchmark, not the pool break (``box2d_peer`` says why); its
column says "not installed" without pyb2d3.

impulse2d's step is compiled (numba): every ``World.step`` is one compiled call, and a
batch is stepped on ``World.threads`` threads (default: every core numba sees, printed in
the header; a single world always uses one). pymunk runs in this one process, Box2D on one
thread (no thread pool).

* Pool break (16 balls, dt = 1/120, 1,200 steps) at 1 world and at ``--worlds`` worlds
  (default 1,024): world-steps/s and us per world-step, with impulse2d's default sleeping
  on and, as a second row, with sleeping off (pymunk never sleeps). The timed loops make
  one ``World.step`` call a step, as an RL loop does; one more single-world row runs the
  whole break in one compiled call (``World.step(dt, steps=1200)``), so the table shows
  both the per-call cost and the compiled run's. impulse2d steps the whole batch at once
  (``World.replicate``); pymunk steps one ``Space`` per world.
* Pool break, varied shots: the same batch, but every world plays its own shot (cue ball
  at y = offset_i, offsets uniform in +-1 cm, ``scenes.pool_cue_offsets``), the realistic
  RL case; impulse2d sleeping on (its default), pymunk sleeping off as elsewhere.
* Box pyramids of base 10 and 20 (dt = 1/60): ms/step over 300 steps, and the top box's
  drift after 600 steps (10 s), impulse2d with sleeping off and its default 4 substeps,
  Box2D with 4 substeps and sleeping off, pymunk 10 iterations.
* Rain of 250, 1,000 and 4,000 circles and boxes onto the ground at the same density
  (``scenes.rain``, dt = 1/60): ms/step over 120 steps after 60 untimed ones, and in the
  notes how the impulse2d time grows from the previous count (linear, not quadratic,
  scaling); impulse2d sleeping off and default substeps, pymunk defaults, Box2D 4 substeps
  and sleeping off.
* Box2D v3's ``large_pyramid`` benchmark (``scenes.large_pyramid``: 100 rows, 5,050 boxes,
  gravity -10, dt = 1/60), impulse2d and Box2D only, both 4 substeps and sleeping off:
  ms/step over its 500 steps from the first, and after them the apex's sink and the
  boxes' sideways creep (largest |dx|, boxes past 0.25 m). About 15 s in all;
  ``--no-large`` skips it, ``--large-budget`` caps the seconds impulse2d's steps are timed.

The issue's targets are checked in the notes of their rows (``engine_rows.py`` lists them).
Checks printed with the table: momentum of the pool break against the analytic
``P0 exp(-drag t)`` until the first cushion contact, every ball on the table and finite,
the largest ball-ball overlap and cushion penetration seen during the break, that
world 0 of the batch ends bitwise equal to the single world, and that worlds of the
varied-shot batch end bitwise equal to single worlds built at their offsets.

Run ``python bench/bench_engine.py`` (about a minute and a half on 2 cores; building the
4,000-body rain world takes about a second, ``World.add`` ~0.3 ms a body), ``--quick`` for
a smoke test, ``--positions`` for the final ball positions of both engines, ``--profile`` for the
per-stage profile of the compiled step (``bench/profile_step.py``) instead of the table.
"""

from __future__ import annotations

import argparse
import os
import platform
import time

import numba
import numpy as np

import impulse2d as p2
from impulse2d.core.runner import available_threads

# _pool_world and _pyramid_world are re-exported: bench_render.py and solver_choice.py import
# these world builders from here.
try:  # imported as part of the repo (``bench.bench_engine``) ...
    from bench import box2d_peer, box2d_scenes, engine_rows, profile_step
    from bench.engine_rows import PYMUNK_SINGLE_REPEATS, PYRAMID_REPEATS, Plan, Row, Runs
    from bench.engine_runs import (
        POOL_RESTITUTION_THRESHOLD,
        POOL_SUBSTEPS,
        PYRAMID_SLEEPING,
        PYRAMID_SUBSTEPS,
        RAIN_SLEEPING,
        _stage,
        set_progress,
    )
    from bench.engine_runs import _pool_world as _pool_world
    from bench.engine_runs import _pyramid_world as _pyramid_world
    from bench.report import print_table, source_version
    from bench.scenes import LATERAL_CREEP_M, large_pyramid, pool_break, pyramid, rain, validate
except ImportError:  # ... or run as a script, with bench/ on sys.path
    import box2d_peer
    import box2d_scenes
    import engine_rows
    import profile_step
    from engine_rows import PYMUNK_SINGLE_REPEATS, PYRAMID_REPEATS, Plan, Row, Runs
    from engine_runs import (
        POOL_RESTITUTION_THRESHOLD,
        POOL_SUBSTEPS,
        PYRAMID_SLEEPING,
        PYRAMID_SUBSTEPS,
        RAIN_SLEEPING,
        _stage,
        set_progress,
    )
    from engine_runs import _pool_world as _pool_world
    from engine_runs import _pyramid_world as _pyramid_world
    from report import print_table, source_version
    from scenes import LATERAL_CREEP_M, large_pyramid, pool_break, pyramid, rain, validate

# -- benchmark settings (the sections' own are in engine_rows.py) ----------------------------
DEFAULT_WORLDS = 1024
BATCH_BUDGET_S = 90.0  # a batch run stops early (timing a prefix of the break) past this
SINGLE_REPEATS = 5  # single-world impulse2d runs; the median is reported
BATCH_REPEATS = 5  # batch runs of each engine, alternating; the median is reported (this
# machine is shared and a single run of either engine can be 30 % off)
RAIN_REPEATS = 3  # timed window of the rain scenes, both engines (1 with --quick)
RAIN_COUNTS = (250, 1000, 4000)
RAIN_COUNTS_QUICK = (250, 1000)
LARGE_STEPS_QUICK = 60  # large_pyramid steps with --quick (the scene's own 500 otherwise)
LARGE_BUDGET_S = 60.0  # seconds of impulse2d's large_pyramid stepping that are timed


# -- setup -----------------------------------------------------------------------------------
def _parse_args(argv: list[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="short smoke test")
    parser.add_argument("--worlds", type=int, default=None, help="worlds in the batch run")
    parser.add_argument(
        "--budget", type=float, default=BATCH_BUDGET_S, help="seconds per impulse2d batch run"
    )
    parser.add_argument("--positions", action="store_true", help="print final ball positions")
    parser.add_argument(
        "--no-box2d-scenes",
        action="store_true",
        help="skip Box2D's shape and joint scenes (joint_grid, smash, tumbler, spinner, "
        "many_pyramids: bench/box2d_scenes.py; minutes at full size)",
    )
    parser.add_argument(
        "--no-large",
        action="store_true",
        help="skip Box2D's large_pyramid benchmark (5,050 boxes, 500 steps; ~15 s of the run)",
    )
    parser.add_argument(
        "--large-budget",
        type=float,
        default=LARGE_BUDGET_S,
        help="seconds of impulse2d's large_pyramid steps that are timed (the rest of the 500 "
        "run untimed; the settling is always measured after 500)",
    )
    parser.add_argument(
        "--profile",
        action="store_true",
        help="per-stage profile of the compiled step (profile_step.py) and exit",
    )
    parser.add_argument("--no-progress", action="store_true", help="no progress output")
    args = parser.parse_args(argv)
    # The batch rows are keyed by world count beside the single-world rows, and one world
    # is already measured there.
    if args.worlds is not None and args.worlds < 2:
        parser.error(
            f"--worlds must be >= 2 (the single world is always measured), got {args.worlds}"
        )
    return args


def _plan(args: argparse.Namespace) -> Plan:
    """The step counts, world count and repeats of this run."""
    scene = pool_break()
    validate(scene)
    pyr_steps, drift_steps = (60, 120) if args.quick else (300, 600)
    rain_counts = RAIN_COUNTS_QUICK if args.quick else RAIN_COUNTS
    large = large_pyramid()
    return Plan(
        quick=args.quick,
        budget=args.budget,
        positions=args.positions,
        scene=scene,
        threads=p2.World().threads,
        pool_steps=120 if args.quick else scene.steps,
        n_worlds=args.worlds or (64 if args.quick else DEFAULT_WORLDS),
        single_repeats=3 if args.quick else SINGLE_REPEATS,
        batch_repeats=1 if args.quick else BATCH_REPEATS,
        pyr_steps=pyr_steps,
        drift_steps=drift_steps,
        dt_pyr=pyramid(1).dt,
        rain_counts=rain_counts,
        rain_repeats=1 if args.quick else RAIN_REPEATS,
        rain_scene=rain(rain_counts[0]),
        large_steps=0 if args.no_large else (LARGE_STEPS_QUICK if args.quick else large.steps),
        large_budget=args.large_budget,
    )


def _print_setup(plan: Plan) -> None:
    """Print the versions, the scenes, both engines' settings and how the timing is done."""
    import pymunk

    scene, pool_steps, dt_pyr = plan.scene, plan.pool_steps, plan.dt_pyr
    pyr_steps, drift_steps, rain_repeats = plan.pyr_steps, plan.drift_steps, plan.rain_repeats
    print("impulse2d vs pymunk and Box2D v3" + (" (--quick)" if plan.quick else ""))
    print(
        f"python {platform.python_version()}, numpy {np.__version__}, numba {numba.__version__}, "
        f"pymunk {pymunk.version} (Chipmunk {pymunk.chipmunk_version[:5]}), {os.cpu_count()} "
        f"CPUs, load average {', '.join(f'{x:.2f}' for x in os.getloadavg())} at start"
    )
    print(f"Box2D v3: {box2d_peer.version()}; {source_version()}")
    print(
        f"threads: impulse2d steps a batch on {plan.threads} (World.threads, its default: "
        f"every core numba sees; impulse2d.core.runner.available_threads() = "
        f"{available_threads()}), a single world on one; pymunk: one process, one thread"
    )
    print(scene.describe().replace(f"{scene.steps} steps", f"{pool_steps} steps"))
    print(
        f"  impulse2d: substeps={POOL_SUBSTEPS}, restitution_mixing='min', "
        f"restitution_threshold={POOL_RESTITUTION_THRESHOLD} m/s, friction 0; sleeping on "
        "(its default: resting balls sleep and cost nothing; what RL users get), plus "
        "'no sleep' rows with sleeping=False"
    )
    print(
        "  pymunk: one Space per world, stepped world by world; 10 iterations, sleeping off; "
        "impulse2d: the whole batch in one World.step call a step (one compiled call)"
    )
    print(
        f"pyramids: dt=1/{1 / dt_pyr:.0f}, {pyr_steps} timed steps, drift of the top box after "
        f"{drift_steps} steps ({drift_steps * dt_pyr:g} s); impulse2d substeps="
        f"{PYRAMID_SUBSTEPS}, sleeping={PYRAMID_SLEEPING}; pymunk 10 iterations"
    )
    print(
        "pool break, varied shots: world i's cue ball starts at y = offset_i, offsets "
        "uniform in [-10, 10] mm (scenes.pool_cue_offsets, seed 0); impulse2d sets them on "
        "the replicated batch (bodies[cue].position = (n, 2) array), pymunk builds each Space "
        "with its own offset"
    )
    print(
        f"{plan.rain_scene.describe()}; {', '.join(map(str, plan.rain_counts))} bodies; impulse2d "
        f"sleeping={RAIN_SLEEPING}, default substeps, ground a Plane; pymunk defaults "
        "(10 iterations, no sleeping, collision_slop 0.1), ground a static box"
    )
    _print_box2d_setup(plan)
    print(
        "timing: perf_counter around the stepping only, after a warm-up step on a separate "
        f"world; single-world pool: median of {plan.single_repeats} (impulse2d) / "
        f"{PYMUNK_SINGLE_REPEATS} (pymunk) runs; batch pool: median of "
        f"{plan.batch_repeats} runs of each; pyramids: median of "
        f"{PYRAMID_REPEATS} (Box2D too); rain: "
        + (
            f"median of {rain_repeats} (impulse2d: windows restored from a snapshot after the "
            "untimed steps; pymunk and Box2D: fresh worlds)"
            if rain_repeats > 1
            else "one run"
        )
    )


def _print_box2d_setup(plan: Plan) -> None:
    """Print what Box2D runs and how (or that pyb2d3 is missing)."""
    large = large_pyramid()
    print(
        f"large_pyramid (Box2D v3's benchmark): {large.n_boxes:,} boxes {large.box_size} m / "
        f"{large.box_mass} kg touching side by side, mu={large.friction}, gravity "
        f"{large.gravity[1]:g}, dt=1/{1 / large.dt:.0f}, "
        + (
            f"{plan.large_steps} steps timed from the first (impulse2d: at most "
            f"{plan.large_budget:g} s of them), then the apex's sink and the sideways creep "
            f"(max |dx|, boxes past {LATERAL_CREEP_M:g} m); impulse2d and Box2D only"
            if plan.large_steps
            else "skipped (--no-large)"
        )
    )
    if not box2d_peer.AVAILABLE:
        print("  Box2D v3: pyb2d3 not installed (pip install -e '.[bench]'): its column is empty")
        return
    print(
        f"  Box2D v3 (via {box2d_peer.version()}): pyramids, rain and large_pyramid, "
        f"world.step(dt, {box2d_peer.SUBSTEPS}) (4 substeps, as its samples), sleeping off, "
        "default contact softness (30 Hz, damping ratio 10, push-out 3 m/s), continuous "
        "collision on, one thread (no thread pool); friction mixed sqrt(f1 f2), restitution "
        "max; ground the scenes' static box; not the pool break (its min restitution mixing "
        "needs a callback pyb2d3 lacks)"
    )


# -- results ---------------------------------------------------------------------------------
def _print_table(rows: list[tuple[str, ...]]) -> None:
    """The table; rows without Box2D cells (the pool break's) get "-" in its columns."""
    header = ("scene", "worlds", "impulse2d", "pymunk", "ratio", "Box2D v3", "ratio B2", "notes")
    align = ("<", ">", ">", ">", ">", ">", ">", "<")
    full = [r if len(r) == len(header) else (*r[:-1], "-", "-", r[-1]) for r in rows]
    print_table(header, align, full)


def _print_results(plan: Plan, rows: list[Row], imp: Runs, pm1: dict) -> None:
    """Print the table and, with ``--positions``, the final ball positions of both engines."""
    print()
    _print_table(rows)
    if not plan.positions:
        return
    print(f"\nfinal ball positions after {plan.pool_steps} steps (m), single world")
    print(
        f"{'ball':>4}  {'impulse2d x':>11} {'y':>8}  {'no-sleep x':>10} {'y':>8}  "
        f"{'pymunk x':>9} {'y':>8}"
    )
    a, b = imp[(1, True)]["final_positions"], imp[(1, False)]["final_positions"]
    pm_final = pm1["final_positions"]
    for i in range(plan.scene.n_balls):
        print(
            f"{i:>4}  {a[i, 0]:>11.4f} {a[i, 1]:>8.4f}  {b[i, 0]:>10.4f} {b[i, 1]:>8.4f}  "
            f"{pm_final[i, 0]:>9.4f} {pm_final[i, 1]:>8.4f}"
        )


def main(argv: list[str] | None = None) -> None:
    """Run every benchmark and print the table."""
    args = _parse_args(argv)
    set_progress(not args.no_progress)
    if args.profile:
        worlds = args.worlds or (64 if args.quick else DEFAULT_WORLDS)
        profile_step.run(worlds, args.quick, _stage)
        return

    t_start = time.perf_counter()
    plan = _plan(args)
    _print_setup(plan)
    rows: list[Row] = []
    imp: Runs = {}  # filled by the pool sections, read by the later ones
    pm1 = engine_rows.pool_single_world(plan, imp, rows)
    engine_rows.pool_one_call(plan, imp, pm1, rows)
    pmN = engine_rows.pool_batch(plan, imp, rows)
    engine_rows.pool_one_substep(plan, pmN, rows)
    engine_rows.pool_batch_matches_single(plan, imp, rows)
    engine_rows.pool_checks(plan, imp, pm1, rows)
    engine_rows.pool_varied_shots(plan, imp, rows)
    engine_rows.pyramids(plan, rows)
    engine_rows.rains(plan, rows)
    engine_rows.settled_rain(plan, rows)
    engine_rows.large_pyramid(plan, rows)
    if not args.no_box2d_scenes:
        rows += box2d_scenes.rows(plan.quick, progress=_stage)
    _print_results(plan, rows, imp, pm1)
    print(
        f"\ntotal wall time {time.perf_counter() - t_start:.1f} s; load average "
        f"{', '.join(f'{x:.2f}' for x in os.getloadavg())} at end"
    )


if __name__ == "__main__":
    main()
