"""Speed benchmark: impulse2d against pymunk (C Chipmunk2D) on the shared scenes, in one run.

The scenes come from ``bench/scenes.py`` and the pymunk side from ``bench/pymunk_peer.py``;
this module builds the same scenes in impulse2d, times both engines in the same process and
prints one table with the two side by side and their ratio (always impulse2d / pymunk, so
for a rate higher is better and for a time lower is better).

* Pool break (16 balls, dt = 1/120, 1,200 steps) at 1 world and at ``--worlds`` worlds
  (default 1,024): world-steps/s and us per world-step, with impulse2d's default sleeping
  on and, as a second row, with sleeping off (pymunk never sleeps). impulse2d steps the
  whole batch at once (``World.replicate``); pymunk steps one ``Space`` per world.
* Pool break, varied shots: the same batch, but every world plays its own shot (cue ball
  at y = offset_i, offsets uniform in +-1 cm, ``scenes.pool_cue_offsets``), the realistic
  RL case; impulse2d sleeping on (its default), pymunk sleeping off as elsewhere.
* Box pyramids of base 10 and 20 (dt = 1/60): ms/step over 300 steps, and the top box's
  drift after 600 steps (10 s), impulse2d with sleeping off and its default 4 substeps.
* Rain of 250, 1,000 and 4,000 circles and boxes onto the ground at the same density
  (``scenes.rain``, dt = 1/60): ms/step over 120 steps after 60 untimed ones, and in the
  notes how the impulse2d time grows from the previous count (linear, not quadratic,
  scaling); impulse2d sleeping off and default substeps, pymunk defaults.

Checks printed with the table: momentum of the pool break against the analytic
``P0 exp(-drag t)`` until the first cushion contact, every ball on the table and finite,
the largest ball-ball overlap and cushion penetration seen during the break, that
world 0 of the batch ends bitwise equal to the single world, and that worlds of the
varied-shot batch end bitwise equal to single worlds built at their offsets.

Run ``python bench/bench_engine.py`` (about 2.5 minutes on 2 cores, 100 s of it building the
4,000-body impulse2d rain world: ``World.add`` costs O(capacity^2)), ``--quick`` for a smoke
test, ``--positions`` for the final ball positions of both engines, ``--profile`` for a
cProfile of pool steps.
"""

from __future__ import annotations

import argparse
import cProfile
import io
import math
import os
import platform
import pstats
import statistics
import sys
import time
from collections.abc import Iterable, Iterator
from typing import Any

import numpy as np

import impulse2d as p2

try:  # imported as part of the repo (``bench.bench_engine``) ...
    from bench import pymunk_peer
    from bench.scenes import (
        PoolBreak,
        Pyramid,
        Rain,
        pool_break,
        pool_cue_offsets,
        pyramid,
        rain,
        validate,
    )
except ImportError:  # ... or run as a script, with bench/ on sys.path
    import pymunk_peer
    from scenes import (
        PoolBreak,
        Pyramid,
        Rain,
        pool_break,
        pool_cue_offsets,
        pyramid,
        rain,
        validate,
    )

# -- impulse2d settings ----------------------------------------------------------------------
POOL_SUBSTEPS = 2  # solver substeps per pool step (to be tuned)
POOL_RESTITUTION_THRESHOLD = 0.05  # m/s: no gravity, so no resting jitter; slow hits bounce
PYRAMID_SUBSTEPS = 4  # impulse2d's default
PYRAMID_SLEEPING = False  # the drift is measured on awake boxes, and so is the timing
RAIN_SLEEPING = False  # the piles would fall asleep; time the awake cost, as pymunk's

# -- benchmark settings ----------------------------------------------------------------------
DEFAULT_WORLDS = 1024
BATCH_BUDGET_S = 90.0  # a batch run stops early (timing a prefix of the break) past this
SINGLE_REPEATS = 5  # single-world impulse2d runs; the median is reported
BATCH_REPEATS = 5  # batch runs of each engine, alternating; the median is reported (this
# machine is shared and a single run of either engine can be 30 % off)
PYMUNK_SINGLE_REPEATS = 7  # single-world pymunk runs take milliseconds
PYRAMID_REPEATS = 3  # timed part of the pyramids, both engines
RAIN_REPEATS = 3  # timed window of the rain scenes, both engines (1 with --quick)
RAIN_COUNTS = (250, 1000, 4000)
RAIN_COUNTS_QUICK = (250, 1000)
MEAN_STEP_TARGET_US = 100.0
PYRAMID_RATIO_TARGET = 5.0


# -- progress (tqdm if installed, otherwise nothing) ------------------------------------------
_SHOW_PROGRESS = True


def _progress(iterable: Iterable[Any], total: int, desc: str) -> Iterator[Any]:
    """Wrap ``iterable`` in a tqdm bar on stderr when tqdm is installed and wanted."""
    if _SHOW_PROGRESS:
        try:
            from tqdm import tqdm
        except ImportError:
            pass
        else:
            # disable=None: no bar when stderr is not a terminal (a log file stays clean).
            yield from tqdm(iterable, total=total, desc=desc, leave=False, disable=None)
            return
    yield from iterable


def _stage(text: str) -> None:
    """Say what is running (stderr, so the table on stdout stays clean)."""
    if _SHOW_PROGRESS:
        print(f"... {text}", file=sys.stderr, flush=True)


# -- pool break ------------------------------------------------------------------------------
def _pool_world(
    scene: PoolBreak, substeps: int, sleeping: bool
) -> tuple[p2.World, list[int], list[int]]:
    """One impulse2d world of the pool break; returns it and the ``bodies`` indices of the
    balls (scene order) and of the cushions."""
    world = p2.World(
        gravity=scene.gravity,
        substeps=substeps,
        restitution_mixing="min",  # balls 0.95, cushions 0.75: ball-ball 0.95, ball-cushion 0.75
        friction_mixing="sqrt",
        restitution_threshold=POOL_RESTITUTION_THRESHOLD,
        sleeping=sleeping,
    )
    cushions = [
        world.add(
            p2.Box(
                position=box.center,
                width=2 * box.half_extents[0],
                height=2 * box.half_extents[1],
                mass=1.0,
                fixed=True,
                restitution=scene.restitution_ball_cushion,
                friction=scene.friction,
            )
        )
        for box in scene.cushions
    ]
    balls = [
        world.add(
            p2.Circle(
                position=(float(p[0]), float(p[1])),
                velocity=(float(v[0]), float(v[1])),
                radius=scene.ball_radius,
                mass=scene.ball_mass,
                restitution=scene.restitution_ball_ball,
                friction=scene.friction,
                linear_drag=scene.linear_drag,
            )
        )
        for p, v in zip(scene.positions, scene.velocities, strict=True)
    ]
    index = {id(body): i for i, body in enumerate(world.bodies)}
    return world, [index[id(b)] for b in balls], [index[id(c)] for c in cushions]


def _positions(world: p2.World, indices: list[int]) -> np.ndarray:
    """Positions of the bodies ``world.bodies[indices]``: (n, 2), or (n, B, 2) in a batch."""
    bodies = world.bodies
    return np.array([bodies[i].position for i in indices], dtype=np.float64)


def _velocities(world: p2.World, indices: list[int]) -> np.ndarray:
    bodies = world.bodies
    return np.array([bodies[i].velocity for i in indices], dtype=np.float64)


def _paired_runs(first: Any, second: Any, repeats: int) -> tuple[dict, dict]:
    """Run two benchmarks alternately ``repeats`` times each (so a busy spell on this shared
    machine slows both alike) and keep the run of median speed of each."""
    runs: tuple[list[dict], list[dict]] = ([], [])
    for _ in range(repeats):
        runs[0].append(first())
        runs[1].append(second())
    return tuple(sorted(r, key=lambda x: x["world_steps_per_s"])[repeats // 2] for r in runs)


def _median_run(run: Any, repeats: int) -> dict:
    """Run a benchmark ``repeats`` times and keep the run of median speed."""
    runs = sorted((run() for _ in range(repeats)), key=lambda r: r["world_steps_per_s"])
    return runs[len(runs) // 2]


def pool_break_impulse2d(
    n_worlds: int = 1,
    steps: int = 1200,
    substeps: int = POOL_SUBSTEPS,
    sleeping: bool = True,
    *,
    budget_s: float | None = None,
    cue_y_offsets: np.ndarray | None = None,
) -> dict:
    """Time ``n_worlds`` impulse2d pool-break worlds, stepped as one batch, for ``steps`` steps.

    A warm-up step runs first on a separate world (a batch of two for a batch run), so
    first-call costs stay out of the timing; the timed world starts fresh, as in pymunk.
    With ``budget_s``, stepping stops once that much time has passed (a prefix of the break
    is timed); ``steps`` in the result says how many steps were done.

    With ``cue_y_offsets`` (``n_worlds`` values, m; see :func:`scenes.pool_cue_offsets`)
    every world plays its own shot: one world is built, replicated, and the cue ball's
    per-world start ``(x, cue_y_offsets[i])`` is set with the batch setter
    ``batch.bodies[cue].position = positions`` (shape (n_worlds, 2)).

    Returns ``world_steps_per_s``, ``seconds``, ``steps``, ``step_us`` (duration of every
    step, single world only, else None), ``final_positions`` of world 0 (n_balls, 2),
    ``final_batch`` (n_balls, n_worlds, 2; batch only, else None), ``worlds_identical``
    (every world of the batch ends exactly as world 0) and ``finite`` (every world).
    """
    scene = pool_break()
    validate(scene)
    dt = scene.dt

    warm, _, _ = _pool_world(scene, substeps, sleeping)
    (warm.replicate(2) if n_worlds > 1 else warm).step(dt)

    world, balls, _ = _pool_world(scene, substeps, sleeping)
    if n_worlds > 1:
        world = world.replicate(n_worlds)
    if cue_y_offsets is not None:
        offsets = np.asarray(cue_y_offsets, dtype=np.float64)
        if offsets.shape != (n_worlds,):
            raise ValueError(f"cue_y_offsets must have shape ({n_worlds},), got {offsets.shape}")
        for y in (offsets.min(), offsets.max()):
            validate(pool_break(float(y)))  # the extreme shots still start on the table
        start = np.repeat(scene.positions[:1], n_worlds, axis=0)  # (n_worlds, 2)
        start[:, 1] = offsets
        world.bodies[balls[0]].position = start if n_worlds > 1 else start[0]

    step = world.step
    clock = time.perf_counter
    step_us = None
    if n_worlds == 1:
        # Per-step durations for the mean/median/max; a clock read costs ~0.1 us a step.
        stamps = np.empty(steps + 1)
        stamps[0] = clock()
        for k in range(steps):
            step(dt)
            stamps[k + 1] = clock()
        done = steps
        seconds = float(stamps[-1] - stamps[0])
        step_us = 1e6 * np.diff(stamps)
    else:
        done = 0
        t0 = clock()
        for _ in _progress(range(steps), steps, f"impulse2d {n_worlds} worlds"):
            step(dt)
            done += 1
            if budget_s is not None and clock() - t0 > budget_s:
                break
        seconds = clock() - t0

    final = _positions(world, balls)  # (n, 2) or (n, B, 2)
    finite = bool(np.all(np.isfinite(final)))
    identical, batch = True, None
    if n_worlds > 1:
        identical = bool(np.all(final == final[:, :1, :]))
        batch, final = final, final[:, 0, :]
    return {
        "world_steps_per_s": n_worlds * done / seconds,
        "seconds": seconds,
        "steps": done,
        "step_us": step_us,
        "final_positions": final,
        "final_batch": batch,
        "worlds_identical": identical,
        "finite": finite,
    }


def pool_check_impulse2d(
    steps: int = 1200, substeps: int = POOL_SUBSTEPS, sleeping: bool = True
) -> dict:
    """Replay one impulse2d pool break untimed and measure what the timing cannot.

    * ``momentum_error``: until the first cushion contact (cushions are external forces)
      the total momentum must equal ``P0 exp(-drag t)``; the largest deviation relative
      to ``|P0|``, over ``momentum_window_s`` seconds.
    * ``max_overlap_m``: the deepest ball-ball overlap seen after any step;
      ``max_penetration_m``: the deepest a ball reached past the play-area edge (into
      a cushion).
    * ``energy_gain``: drag scales kinetic energy by ``exp(-2 drag t)`` and collisions with
      ``e <= 1`` can only remove energy, so ``KE(t) / (KE0 exp(-2 drag t))`` must stay
      <= 1; the largest value seen, and ``energy_gain_step``, the step where it occurred.
    * ``final_positions``, ``on_table`` (balls whose centres end inside the play area),
      ``finite``.
    """
    scene = pool_break()
    world, balls, cushions = _pool_world(scene, substeps, sleeping)
    r, dt, drag = scene.ball_radius, scene.dt, scene.linear_drag
    half = np.array(scene.play_area) / 2
    upper = np.triu(np.ones((len(balls), len(balls)), dtype=bool), k=1)
    cushion_slots = np.array([world.bodies[i].slot for i in cushions])

    p0 = scene.ball_mass * scene.velocities.sum(axis=0)
    worst, window, touched = 0.0, 0.0, False
    max_overlap, max_penetration = 0.0, 0.0
    ke0 = _kinetic(scene.ball_mass, scene.velocities)
    gain, gain_step = 1.0, 0
    for k in range(1, steps + 1):
        world.step(dt)
        ratio = _kinetic(scene.ball_mass, _velocities(world, balls)) / (
            ke0 * math.exp(-2 * drag * k * dt)
        )
        if ratio > gain:
            gain, gain_step = ratio, k
        pos = _positions(world, balls)
        dist = np.linalg.norm(pos[:, None, :] - pos[None, :, :], axis=-1)
        max_overlap = max(max_overlap, float((2 * r - dist)[upper].max()))
        max_penetration = max(max_penetration, float((np.abs(pos) + r - half).max()))
        if not touched:
            c = world.last_contacts
            if c is not None and c.size:
                # Single world: flat body index == slot.
                on_cushion = np.isin(c.body_a, cushion_slots) | np.isin(c.body_b, cushion_slots)
                pushed = (c.max_normal_impulse > 0.0) | (c.normal_impulse > 0.0)
                touched = bool(np.any(on_cushion & pushed))
            if not touched:
                momentum = scene.ball_mass * _velocities(world, balls).sum(axis=0)
                expected = p0 * math.exp(-drag * k * dt)
                worst = max(worst, float(np.linalg.norm(momentum - expected)))
                window = k * dt
    final = _positions(world, balls)
    return {
        "momentum_error": worst / float(np.linalg.norm(p0)),
        "momentum_window_s": window,
        "energy_gain": gain,
        "energy_gain_step": gain_step,
        "max_overlap_m": max(max_overlap, 0.0),
        "max_penetration_m": max(max_penetration, 0.0),
        "final_positions": final,
        "on_table": int(np.sum(np.all(np.abs(final) < half, axis=1))),
        "finite": bool(np.all(np.isfinite(final))),
    }


def _kinetic(mass: float, velocities: np.ndarray) -> float:
    """Translational kinetic energy of equal-mass balls (friction 0: they never spin)."""
    return 0.5 * mass * float(np.sum(np.square(velocities)))


def pool_energy_pymunk(steps: int = 1200) -> tuple[float, int]:
    """The same energy check as :func:`pool_check_impulse2d` on an untimed pymunk replay:
    the largest ``KE(t) / (KE0 exp(-2 drag t))`` and the step where it occurred."""
    scene = pool_break()
    space, balls = pymunk_peer._pool_space(scene)
    ke0 = _kinetic(scene.ball_mass, scene.velocities)
    gain, gain_step = 1.0, 0
    for k in range(1, steps + 1):
        space.step(scene.dt)
        v = np.array([tuple(b.velocity) for b in balls])
        ratio = _kinetic(scene.ball_mass, v) / (
            ke0 * math.exp(-2 * scene.linear_drag * k * scene.dt)
        )
        if ratio > gain:
            gain, gain_step = ratio, k
    return gain, gain_step


def _single_positions(
    steps: int, substeps: int, sleeping: bool, cue_y_offset: float = 0.0
) -> np.ndarray:
    """Final ball positions of one world after ``steps`` steps (untimed), built directly
    from ``pool_break(cue_y_offset)``."""
    scene = pool_break(cue_y_offset)
    world, balls, _ = _pool_world(scene, substeps, sleeping)
    for _ in range(steps):
        world.step(scene.dt)
    return _positions(world, balls)


# -- pyramid ---------------------------------------------------------------------------------
def _pyramid_world(scene: Pyramid) -> tuple[p2.World, list[int]]:
    """The pyramid in impulse2d; returns the world and the ``bodies`` indices of the boxes."""
    world = p2.World(gravity=scene.gravity, substeps=PYRAMID_SUBSTEPS, sleeping=PYRAMID_SLEEPING)
    g = scene.ground
    world.add(
        p2.Box(
            position=g.center,
            width=2 * g.half_extents[0],
            height=2 * g.half_extents[1],
            mass=1.0,
            fixed=True,
            friction=scene.friction,
            restitution=scene.restitution,
        )
    )
    boxes = [
        world.add(
            p2.Box(
                position=(float(p[0]), float(p[1])),
                width=scene.box_size,
                height=scene.box_size,
                mass=scene.box_mass,
                friction=scene.friction,
                restitution=scene.restitution,
            )
        )
        for p in scene.positions
    ]
    index = {id(body): i for i, body in enumerate(world.bodies)}
    return world, [index[id(b)] for b in boxes]


def pyramid_impulse2d(
    base: int, steps: int = 300, drift_steps: int = 600, *, repeats: int = 1
) -> dict:
    """Time the first ``steps`` steps of an impulse2d box pyramid, then measure its drift.

    Mirrors :func:`pymunk_peer.pyramid_pymunk`: after a warm-up step on a separate world,
    a fresh world is timed from its first step (median of ``repeats`` fresh worlds), and
    one of them continues untimed to ``drift_steps``; ``top_drift_m`` is how far the top
    box's centre has moved from its start, ``max_drift_m`` the largest over all boxes.
    """
    scene = pyramid(base)
    validate(scene)
    warm, _ = _pyramid_world(scene)
    warm.step(scene.dt)

    timings = []
    for _ in range(repeats):
        world, boxes = _pyramid_world(scene)
        step, dt = world.step, scene.dt
        t0 = time.perf_counter()
        for _ in range(steps):
            step(dt)
        timings.append(time.perf_counter() - t0)
    for _ in range(steps, drift_steps):
        step(dt)

    pos = _positions(world, boxes)
    drift = np.linalg.norm(pos - scene.positions, axis=1)
    return {
        "ms_per_step": 1000 * statistics.median(timings) / steps,
        "top_drift_m": float(drift[scene.top_index]),
        "max_drift_m": float(drift.max()),
        "finite": bool(np.all(np.isfinite(pos))),
    }


# -- rain ------------------------------------------------------------------------------------
def _rain_world(scene: Rain) -> tuple[p2.World, list[int]]:
    """The rain scene in impulse2d (ground: a plane at y = 0); returns the world and the
    ``bodies`` indices of the falling bodies in scene order."""
    world = p2.World(gravity=scene.gravity, sleeping=RAIN_SLEEPING)  # default substeps
    world.add(
        p2.Plane(
            normal=(0.0, 1.0),
            point=(0.0, 0.0),
            friction=scene.friction,
            restitution=scene.restitution,
        )
    )
    r, (w, h) = scene.circle_radius, scene.box_size
    common = {"mass": scene.mass, "friction": scene.friction, "restitution": scene.restitution}
    bodies = [
        world.add(
            p2.Circle(position=(float(p[0]), float(p[1])), radius=r, **common)
            if is_circle
            else p2.Box(
                position=(float(p[0]), float(p[1])), angle=float(a), width=w, height=h, **common
            )
        )
        for p, a, is_circle in zip(scene.positions, scene.angles, scene.is_circle, strict=True)
    ]
    index = {id(body): i for i, body in enumerate(world.bodies)}
    return world, [index[id(b)] for b in bodies]


def rain_impulse2d(
    count: int, steps: int = 120, settle_steps: int = 60, *, repeats: int = 1
) -> dict:
    """Time ``steps`` steps of the impulse2d rain scene after ``settle_steps`` untimed ones.

    Mirrors :func:`pymunk_peer.rain_pymunk`. The untimed steps also warm up. With
    ``repeats`` > 1 the state after the untimed steps is snapshotted and the timed window
    is run ``repeats`` times from it (``World.restore``), reporting the median: building the
    world is what costs at large counts, not stepping it.

    Returns ``ms_per_step``, ``build_s`` (building the world, untimed), ``mean_y`` (mean
    height of the bodies' centres at the end, m), ``finite`` and ``repeats_identical``
    (every timed window ended in the same state).
    """
    scene = rain(count)
    validate(scene)
    t0 = time.perf_counter()
    world, bodies = _rain_world(scene)
    build_s = time.perf_counter() - t0
    step, dt = world.step, scene.dt
    for _ in range(settle_steps):
        step(dt)
    settled = world.snapshot() if repeats > 1 else None
    timings, finals = [], []
    for k in range(repeats):
        if k:
            world.restore(settled)
        t0 = time.perf_counter()
        for _ in _progress(range(steps), steps, f"impulse2d rain {count}"):
            step(dt)
        timings.append(time.perf_counter() - t0)
        finals.append(_positions(world, bodies))
    pos = finals[-1]
    return {
        "ms_per_step": 1000 * statistics.median(timings) / steps,
        "build_s": build_s,
        "mean_y": float(pos[:, 1].mean()),
        "finite": bool(np.all(np.isfinite(pos))),
        "repeats_identical": all(np.array_equal(f, finals[0]) for f in finals),
    }


# -- profile ---------------------------------------------------------------------------------
def profile_pool(n_worlds: int, start: int, steps: int, top: int = 15) -> str:
    """cProfile of ``steps`` pool steps of ``n_worlds`` worlds after ``start`` unprofiled steps,
    sorted by tottime; returns the report text."""
    scene = pool_break()
    world, _, _ = _pool_world(scene, POOL_SUBSTEPS, True)
    if n_worlds > 1:
        world = world.replicate(n_worlds)
    for _ in range(start):
        world.step(scene.dt)
    profiler = cProfile.Profile()
    profiler.enable()
    for _ in range(steps):
        world.step(scene.dt)
    profiler.disable()
    out = io.StringIO()
    pstats.Stats(profiler, stream=out).sort_stats("tottime").print_stats(top)
    head = f"cProfile: {n_worlds} world(s), {steps} step(s) from step {start}, sleeping on\n"
    return head + out.getvalue()


# -- table -----------------------------------------------------------------------------------
def _fmt(value: float | None, digits: int = 3) -> str:
    """A number for the table: thousands separators for big ones, 3 significant digits else."""
    if value is None:
        return "-"
    if isinstance(value, (bool, np.bool_)):
        return str(bool(value))
    if isinstance(value, str):
        return value
    if not math.isfinite(value):
        return str(value)
    if abs(value) >= 1000:
        return f"{value:,.0f}"
    return f"{value:.{digits}g}"


def _ratio(a: float | None, b: float | None) -> str:
    if a is None or b is None or b == 0:
        return "-"
    return f"{a / b:.3g}"


def _print_table(rows: list[tuple[str, ...]]) -> None:
    header = ("scene", "worlds", "impulse2d", "pymunk", "ratio", "notes")
    align = ("<", ">", ">", ">", ">", "<")
    widths = [max(len(r[i]) for r in [header, *rows]) for i in range(len(header))]

    def line(cells: tuple[str, ...]) -> str:
        return "  ".join(f"{c:{a}{w}}" for c, a, w in zip(cells, align, widths, strict=True))

    print(line(header).rstrip())
    print("  ".join("-" * w for w in widths))
    for row in rows:
        print(line(row).rstrip())


def _source_version() -> str:
    """Where impulse2d is imported from and its git commit (``+dirty`` with local changes)."""
    import subprocess

    root = os.path.dirname(os.path.abspath(p2.__file__))
    try:
        rev = subprocess.run(
            ["git", "-C", root, "describe", "--always", "--dirty=+dirty"],
            capture_output=True,
            text=True,
            timeout=5,
            check=True,
        ).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        rev = "no git"
    return f"impulse2d from {root} ({rev})"


def _ok(flag: bool) -> str:
    return "ok" if flag else "MISS"


def main(argv: list[str] | None = None) -> None:
    """Run every benchmark and print the table."""
    global _SHOW_PROGRESS
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="short smoke test")
    parser.add_argument("--worlds", type=int, default=None, help="worlds in the batch run")
    parser.add_argument(
        "--budget", type=float, default=BATCH_BUDGET_S, help="seconds per impulse2d batch run"
    )
    parser.add_argument("--positions", action="store_true", help="print final ball positions")
    parser.add_argument("--profile", action="store_true", help="cProfile pool steps and exit")
    parser.add_argument("--no-progress", action="store_true", help="no progress output")
    args = parser.parse_args(argv)
    _SHOW_PROGRESS = not args.no_progress

    if args.profile:
        print(profile_pool(args.worlds or DEFAULT_WORLDS, start=30, steps=5))
        print(profile_pool(1, start=30, steps=100))
        return

    t_start = time.perf_counter()
    scene = pool_break()
    validate(scene)
    pool_steps = 120 if args.quick else scene.steps
    n_worlds = args.worlds or (64 if args.quick else DEFAULT_WORLDS)
    pyr_steps, drift_steps = (60, 120) if args.quick else (300, 600)
    single_repeats = 3 if args.quick else SINGLE_REPEATS
    dt_pyr = pyramid(1).dt

    import pymunk

    print("impulse2d vs pymunk" + (" (--quick)" if args.quick else ""))
    print(
        f"python {platform.python_version()}, numpy {np.__version__}, pymunk {pymunk.version} "
        f"(Chipmunk {pymunk.chipmunk_version[:5]}), {os.cpu_count()} CPUs"
    )
    print(_source_version())
    print(scene.describe().replace(f"{scene.steps} steps", f"{pool_steps} steps"))
    print(
        f"  impulse2d: substeps={POOL_SUBSTEPS}, restitution_mixing='min', "
        f"restitution_threshold={POOL_RESTITUTION_THRESHOLD} m/s, friction 0; sleeping on "
        "(its default: resting balls sleep and cost nothing; what RL users get), plus "
        "'no sleep' rows with sleeping=False"
    )
    print(
        "  pymunk: one Space per world, stepped world by world; 10 iterations, sleeping off; "
        "impulse2d: the whole batch in one World.step"
    )
    print(
        f"pyramids: dt=1/{1 / dt_pyr:.0f}, {pyr_steps} timed steps, drift of the top box after "
        f"{drift_steps} steps ({drift_steps * dt_pyr:g} s); impulse2d substeps="
        f"{PYRAMID_SUBSTEPS}, sleeping={PYRAMID_SLEEPING}; pymunk 10 iterations"
    )
    rain_counts = RAIN_COUNTS_QUICK if args.quick else RAIN_COUNTS
    rain_repeats = 1 if args.quick else RAIN_REPEATS
    rain_scene = rain(rain_counts[0])
    print(
        "pool break, varied shots: world i's cue ball starts at y = offset_i, offsets "
        "uniform in [-10, 10] mm (scenes.pool_cue_offsets, seed 0); impulse2d sets them on "
        "the replicated batch (bodies[cue].position = (n, 2) array), pymunk builds each Space "
        "with its own offset"
    )
    print(
        f"{rain_scene.describe()}; {', '.join(map(str, rain_counts))} bodies; impulse2d "
        f"sleeping={RAIN_SLEEPING}, default substeps, ground a Plane; pymunk defaults "
        "(10 iterations, no sleeping, collision_slop 0.1), ground a static box"
    )
    print(
        "timing: perf_counter around the stepping only, after a warm-up step on a separate "
        f"world; single-world pool: median of {single_repeats} (impulse2d) / "
        f"{PYMUNK_SINGLE_REPEATS} (pymunk) runs; batch pool: median of "
        f"{1 if args.quick else BATCH_REPEATS} runs of each; pyramids: median of "
        f"{PYRAMID_REPEATS}; rain: "
        + (
            f"median of {rain_repeats} (impulse2d: windows restored from a snapshot after the "
            "untimed steps; pymunk: fresh spaces)"
            if rain_repeats > 1
            else "one run"
        )
    )

    rows: list[tuple[str, ...]] = []
    imp: dict[tuple[int, bool], dict] = {}

    # -- pool break, single world ------------------------------------------------------------
    for sleeping in (True, False):
        _stage(f"impulse2d pool break, 1 world, sleeping={sleeping}")
        runs = [
            pool_break_impulse2d(1, pool_steps, POOL_SUBSTEPS, sleeping)
            for _ in range(single_repeats)
        ]
        deterministic = all(
            np.array_equal(r["final_positions"], runs[0]["final_positions"]) for r in runs
        )
        res = sorted(runs, key=lambda r: r["seconds"])[single_repeats // 2]
        res["deterministic"] = deterministic
        imp[(1, sleeping)] = res
    _stage("pymunk pool break, 1 world")
    pm_runs = [pymunk_peer.pool_break_pymunk(1, pool_steps) for _ in range(PYMUNK_SINGLE_REPEATS)]
    pm1 = sorted(pm_runs, key=lambda r: r["seconds"])[PYMUNK_SINGLE_REPEATS // 2]

    # -- pool break, batch -------------------------------------------------------------------
    repeats = 1 if args.quick else BATCH_REPEATS
    _stage(f"impulse2d and pymunk pool break, {n_worlds} worlds, alternating")
    imp[(n_worlds, True)], pmN = _paired_runs(
        lambda: pool_break_impulse2d(
            n_worlds, pool_steps, POOL_SUBSTEPS, True, budget_s=args.budget
        ),
        lambda: pymunk_peer.pool_break_pymunk(n_worlds, pool_steps),
        repeats,
    )
    _stage(f"impulse2d pool break, {n_worlds} worlds, sleeping=False")
    imp[(n_worlds, False)] = _median_run(
        lambda: pool_break_impulse2d(
            n_worlds, pool_steps, POOL_SUBSTEPS, False, budget_s=args.budget
        ),
        repeats,
    )
    batch_steps = pool_steps

    def pool_rows(n: int, pm: dict) -> None:
        for sleeping in (True, False):
            r = imp[(n, sleeping)]
            tag = "" if sleeping else ", no sleep"
            who = "impulse2d sleeping on" if sleeping else "impulse2d sleeping=False"
            partial = (
                f"; first {r['steps']} of {pool_steps} steps (budget {args.budget:g} s)"
                if r["steps"] < pool_steps
                else f"; {r['steps']} steps"
            )
            if n > 1 and pm is pmN and batch_steps != r["steps"]:
                partial += f"; pymunk {batch_steps} steps"
            ws_i, ws_p = r["world_steps_per_s"], pm["world_steps_per_s"]
            rows.append(
                (
                    f"pool break{tag}: world-steps/s",
                    str(n),
                    _fmt(ws_i),
                    _fmt(ws_p),
                    _ratio(ws_i, ws_p),
                    who + partial,
                )
            )
            rows.append(
                (
                    f"pool break{tag}: us/world-step",
                    str(n),
                    _fmt(1e6 / ws_i),
                    _fmt(1e6 / ws_p),
                    _ratio(1e6 / ws_i, 1e6 / ws_p),
                    "lower is better",
                )
            )
            if n == 1:
                us = r["step_us"]
                mean = float(us.mean())
                rows.append(
                    (
                        f"pool break{tag}: mean us/step",
                        "1",
                        _fmt(mean),
                        "-",
                        "-",
                        f"target < {MEAN_STEP_TARGET_US:g} us: {_ok(mean < MEAN_STEP_TARGET_US)}; "
                        f"median {np.median(us):.0f}, max {us.max():.0f} us "
                        f"(step {int(us.argmax()) + 1})",
                    )
                )

    pool_rows(1, pm1)
    pool_rows(n_worlds, pmN)

    # The same batch with one substep: cheaper, at the cost of deeper overlaps in the rack.
    _stage(f"impulse2d pool break, {n_worlds} worlds, substeps=1")
    one = _median_run(
        lambda: pool_break_impulse2d(n_worlds, pool_steps, 1, True, budget_s=args.budget),
        repeats,
    )
    one_check = pool_check_impulse2d(pool_steps, 1, True)
    rows.append(
        (
            "pool break, substeps=1: world-steps/s",
            str(n_worlds),
            _fmt(one["world_steps_per_s"]),
            _fmt(pmN["world_steps_per_s"]),
            _ratio(one["world_steps_per_s"], pmN["world_steps_per_s"]),
            f"impulse2d sleeping on, 1 substep (h = 1/120 s); deepest ball overlap "
            f"{one_check['max_overlap_m'] * 1e3:.1f} mm (2 substeps: see below); pymunk as above",
        )
    )

    for sleeping in (True, False):
        r = imp[(n_worlds, sleeping)]
        if r["steps"] == pool_steps:
            single = imp[(1, sleeping)]["final_positions"]
        else:
            _stage(f"impulse2d single-world replay of {r['steps']} steps")
            single = _single_positions(r["steps"], POOL_SUBSTEPS, sleeping)
        equal = bool(np.array_equal(r["final_positions"], single))
        diff = float(np.abs(r["final_positions"] - single).max())
        tag = "" if sleeping else ", no sleep"
        rows.append(
            (
                f"pool break{tag}: world 0 == 1 world",
                str(n_worlds),
                str(equal),
                "-",
                "-",
                f"bitwise, after {r['steps']} steps (max |diff| {diff:.3g} m); all {n_worlds} "
                f"worlds identical: {r['worlds_identical']}; 1-world repeats identical: "
                f"{imp[(1, sleeping)]['deterministic']}",
            )
        )

    # -- pool break checks -------------------------------------------------------------------
    _stage("impulse2d pool break, untimed check replay")
    chk = pool_check_impulse2d(pool_steps, POOL_SUBSTEPS, True)
    replay_same = bool(np.array_equal(chk["final_positions"], imp[(1, True)]["final_positions"]))
    rows.append(
        (
            "pool break: momentum rel. error",
            "1",
            f"{chk['momentum_error']:.1e}",
            f"{pm1['momentum_error']:.1e}",
            "-",
            f"vs P0 exp(-0.7 t) until first cushion contact: {chk['momentum_window_s']:.3f} s "
            f"(pymunk {pm1['momentum_window_s']:.3f} s)",
        )
    )
    pm_gain, pm_gain_step = pool_energy_pymunk(pool_steps)
    rows.append(
        (
            "pool break: max energy gain",
            "1",
            f"{chk['energy_gain']:.4f}",
            f"{pm_gain:.4f}",
            "-",
            f"max KE(t) / (KE0 exp(-1.4 t)), must be <= 1; at step {chk['energy_gain_step']} "
            f"(pymunk step {pm_gain_step})",
        )
    )
    half = np.array(scene.play_area) / 2
    pm_final = pm1["final_positions"]
    pm_on = int(np.sum(np.all(np.abs(pm_final) < half, axis=1)))
    n_balls = scene.n_balls
    rows.append(
        (
            "pool break: balls on table",
            "1",
            f"{chk['on_table']}/{n_balls}",
            f"{pm_on}/{n_balls}",
            "-",
            f"finite: {chk['finite'] and all(r['finite'] for r in imp.values())}; replay == timed "
            f"run: {replay_same}",
        )
    )
    rows.append(
        (
            "pool break: max overlap (mm)",
            "1",
            _fmt(1e3 * chk["max_overlap_m"]),
            "-",
            "-",
            f"deepest ball-ball overlap after any step; deepest past a cushion face "
            f"{1e3 * chk['max_penetration_m']:.3g} mm",
        )
    )

    # -- pool break, varied shots (one shot per world) ---------------------------------------
    offsets = pool_cue_offsets(n_worlds)
    _stage(f"impulse2d and pymunk pool break, varied shots, {n_worlds} worlds, alternating")
    var, pmV = _paired_runs(
        lambda: pool_break_impulse2d(
            n_worlds, pool_steps, POOL_SUBSTEPS, True, budget_s=args.budget, cue_y_offsets=offsets
        ),
        lambda: pymunk_peer.pool_break_pymunk(n_worlds, pool_steps, offsets),
        1 if args.quick else BATCH_REPEATS,
    )
    ws_i, ws_p = var["world_steps_per_s"], pmV["world_steps_per_s"]
    same_shot = imp[(n_worlds, True)]
    vs_same = (
        f"; x{ws_i / same_shot['world_steps_per_s']:.2f} the identical-shot impulse2d rate"
        if same_shot["steps"] == var["steps"]
        else ""
    )
    steps_note = (
        f"first {var['steps']} of {pool_steps} steps (budget {args.budget:g} s)"
        if var["steps"] < pool_steps
        else f"{var['steps']} steps"
    )
    rows.append(
        (
            "pool break, varied shots: world-steps/s",
            str(n_worlds),
            _fmt(ws_i),
            _fmt(ws_p),
            _ratio(ws_i, ws_p),
            f"impulse2d sleeping on (its default), pymunk sleeping off as elsewhere; "
            f"{steps_note}{vs_same}",
        )
    )
    rows.append(
        (
            "pool break, varied shots: us/world-step",
            str(n_worlds),
            _fmt(1e6 / ws_i),
            _fmt(1e6 / ws_p),
            _ratio(1e6 / ws_i, 1e6 / ws_p),
            "lower is better",
        )
    )
    # World i of the batch (cue moved with the batch setter) against a single world built
    # directly from pool_break(offsets[i]): the setter must give the same start.
    batch_final = var["final_batch"]
    checked = sorted({0, n_worlds - 1})
    _stage(f"impulse2d single-world replays of varied shots {checked}")
    diffs = [
        float(
            np.abs(
                batch_final[:, i, :]
                - _single_positions(var["steps"], POOL_SUBSTEPS, True, float(offsets[i]))
            ).max()
        )
        for i in checked
    ]
    distinct = len({batch_final[:, i, :].tobytes() for i in range(n_worlds)})
    rows.append(
        (
            "pool break, varied shots: world i == 1 world",
            str(n_worlds),
            str(all(d == 0.0 for d in diffs)),
            "-",
            "-",
            f"bitwise, worlds {checked} against single worlds built at their offsets (max |diff| "
            f"{max(diffs):.3g} m); {distinct} of {n_worlds} final states distinct; finite: "
            f"{var['finite']}; pymunk world 0 momentum err {pmV['momentum_error']:.1e}",
        )
    )

    # -- pyramids ----------------------------------------------------------------------------
    for base in (10, 20):
        _stage(f"pyramid base {base}")
        ri = pyramid_impulse2d(base, pyr_steps, drift_steps, repeats=PYRAMID_REPEATS)
        pm_runs = [pymunk_peer.pyramid_pymunk(base, pyr_steps, drift_steps) for _ in range(3)]
        rp = sorted(pm_runs, key=lambda r: r["ms_per_step"])[1]
        ratio = ri["ms_per_step"] / rp["ms_per_step"]
        rows.append(
            (
                f"pyramid base {base}: ms/step",
                "1",
                _fmt(ri["ms_per_step"]),
                _fmt(rp["ms_per_step"]),
                _ratio(ri["ms_per_step"], rp["ms_per_step"]),
                f"target ratio <= {PYRAMID_RATIO_TARGET:g}: {_ok(ratio <= PYRAMID_RATIO_TARGET)}",
            )
        )
        rows.append(
            (
                f"pyramid base {base}: top drift (m)",
                "1",
                f"{ri['top_drift_m']:.4f}",
                f"{rp['top_drift_m']:.4f}",
                _ratio(ri["top_drift_m"], rp["top_drift_m"]),
                f"after {drift_steps * dt_pyr:g} s; target <= pymunk: "
                f"{_ok(ri['top_drift_m'] <= rp['top_drift_m'])}; max drift "
                f"{ri['max_drift_m']:.4f} / {rp['max_drift_m']:.4f} m; finite: {ri['finite']}",
            )
        )

    # -- rain: cost against scene size --------------------------------------------------------
    previous: tuple[int, dict, dict] | None = None
    for count in rain_counts:
        _stage(f"rain {count} bodies (impulse2d builds, settles and steps, then pymunk)")
        ri = rain_impulse2d(count, rain_scene.steps, rain_scene.settle_steps, repeats=rain_repeats)
        pm_runs = [
            pymunk_peer.rain_pymunk(count, rain_scene.steps, rain_scene.settle_steps)
            for _ in range(rain_repeats)
        ]
        rp = sorted(pm_runs, key=lambda r: r["ms_per_step"])[rain_repeats // 2]
        growth = ""
        if previous is not None:
            n0, ri0, rp0 = previous
            growth = (
                f"x{ri['ms_per_step'] / ri0['ms_per_step']:.2f} for {count / n0:g}x the bodies "
                f"(pymunk x{rp['ms_per_step'] / rp0['ms_per_step']:.2f}); "
            )
        rows.append(
            (
                f"rain {count} bodies: ms/step",
                "1",
                _fmt(ri["ms_per_step"]),
                _fmt(rp["ms_per_step"]),
                _ratio(ri["ms_per_step"], rp["ms_per_step"]),
                f"{growth}mean height {ri['mean_y']:.3f} / {rp['mean_y']:.3f} m; finite: "
                f"{ri['finite'] and rp['finite']}; repeats identical: "
                f"{ri['repeats_identical']}; impulse2d build {ri['build_s']:.1f} s (untimed)",
            )
        )
        previous = (count, ri, rp)

    print()
    if batch_steps < pool_steps:
        print(
            f"NOTE: the {n_worlds}-world impulse2d runs passed the {args.budget:g} s budget, so "
            f"only a prefix of the break was timed (first {batch_steps} of {pool_steps} steps; "
            "see notes); pymunk was timed over the same prefix\n"
        )
    _print_table(rows)

    if args.positions:
        print(f"\nfinal ball positions after {pool_steps} steps (m), single world")
        print(
            f"{'ball':>4}  {'impulse2d x':>11} {'y':>8}  {'no-sleep x':>10} {'y':>8}  "
            f"{'pymunk x':>9} {'y':>8}"
        )
        a, b = imp[(1, True)]["final_positions"], imp[(1, False)]["final_positions"]
        for i in range(n_balls):
            print(
                f"{i:>4}  {a[i, 0]:>11.4f} {a[i, 1]:>8.4f}  {b[i, 0]:>10.4f} {b[i, 1]:>8.4f}  "
                f"{pm_final[i, 0]:>9.4f} {pm_final[i, 1]:>8.4f}"
            )

    print(f"\ntotal wall time {time.perf_counter() - t_start:.1f} s")


if __name__ == "__main__":
    main()
