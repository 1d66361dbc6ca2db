"""The impulse2d side of the engine benchmark (``bench/bench_engine.py``).

Builds the shared scenes of ``bench/scenes.py`` (pool break, box pyramids, rain) as impulse2d
worlds, times them the way ``bench/pymunk_peer.py`` times pymunk, and replays the pool break
untimed for what the timing cannot measure: momentum against ``P0 exp(-drag t)``, energy
gain (impulse2d, and pymunk for comparison), overlaps and penetration. ``bench_engine.main``
runs these and prints the table; ``bench/profile_step.py`` (``--profile``) reuses the world
builders.

Every ``World.step`` is one compiled call (``impulse2d.core.pipeline``). The timed loops call it
once per step from Python, as an RL loop or a game does, except
:func:`pool_break_one_call`, which passes ``steps=`` and runs the whole break in one call.
A batch is stepped on ``World.threads`` threads (default: every core numba sees).
"""

from __future__ import annotations

import math
import statistics
import sys
import time
from collections.abc import Iterable, Iterator
from typing import Any

import numpy as np

import impulse2d as p2

try:  # imported as part of the repo (``bench.engine_runs``) ...
    from bench.scenes import (
        PoolBreak,
        Pyramid,
        Rain,
        large_pyramid,
        pool_break,
        pyramid,
        pyramid_settling,
        rain,
        validate,
    )
except ImportError:  # ... or run as a script, with bench/ on sys.path
    from scenes import (
        PoolBreak,
        Pyramid,
        Rain,
        large_pyramid,
        pool_break,
        pyramid,
        pyramid_settling,
        rain,
        validate,
    )

# -- impulse2d settings ----------------------------------------------------------------------
POOL_SUBSTEPS = 2  # solver substeps per pool step (to be tuned)
POOL_RESTITUTION_THRESHOLD = 0.05  # m/s: no gravity, so no resting jitter; slow hits bounce
PYRAMID_SUBSTEPS = 4  # impulse2d's default
PYRAMID_SLEEPING = False  # the drift is measured on awake boxes, and so is the timing
RAIN_SLEEPING = False  # the piles would fall asleep; time the awake cost, as pymunk's

# -- progress (tqdm if installed, otherwise nothing) ------------------------------------------
_SHOW_PROGRESS = True


def set_progress(show: bool) -> None:
    """Show progress (bars and stage lines on stderr) or not: ``--no-progress``."""
    global _SHOW_PROGRESS
    _SHOW_PROGRESS = show


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
    scene: PoolBreak, substeps: int, sleeping: bool, device: str = "cpu"
) -> tuple[p2.World, list[int], list[int]]:
    """One impulse2d world of the pool break (stepped on ``device``); returns it and the
    ``bodies`` indices of the balls (scene order) and of the cushions."""
    world = p2.World(
        gravity=scene.gravity,
        device=device,
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


def pool_batch_world(
    n_worlds: int,
    substeps: int = POOL_SUBSTEPS,
    sleeping: bool = True,
    cue_y_offsets: np.ndarray | None = None,
    device: str = "cpu",
) -> tuple[p2.World, list[int]]:
    """The pool break in ``n_worlds`` worlds (one world, or a ``replicate``d batch) and the
    ``bodies`` indices of its balls. With ``cue_y_offsets`` (``n_worlds`` values, m; see
    :func:`scenes.pool_cue_offsets`) every world plays its own shot: the cue ball's
    per-world start ``(x, cue_y_offsets[i])`` is set with the batch setter
    ``batch.bodies[cue].position = positions`` (shape (n_worlds, 2)). ``device``: where the
    batch steps (``World(device=...)``)."""
    scene = pool_break()
    validate(scene)
    world, balls, _ = _pool_world(scene, substeps, sleeping, device)
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
    return world, balls


def _timed_steps(
    world: p2.World, dt: float, steps: int, budget_s: float | None
) -> tuple[int, float, np.ndarray | None]:
    """Step ``world`` ``steps`` times, one ``World.step`` call a step; returns the steps
    done, the seconds and, for a single world, the duration of every step (us). A batch
    stops early once ``budget_s`` has passed (a prefix of the break is timed)."""
    step, clock = world.step, time.perf_counter
    if world.batch_size == 1:
        # Per-step durations for the mean/median/max; a clock read costs ~0.1 us a step.
        stamps = np.empty(steps + 1)
        stamps[0] = clock()
        for k in range(steps):
            step(dt)
            stamps[k + 1] = clock()
        return steps, float(stamps[-1] - stamps[0]), 1e6 * np.diff(stamps)
    done = 0
    t0 = clock()
    for _ in _progress(range(steps), steps, f"impulse2d {world.batch_size} worlds"):
        step(dt)
        done += 1
        if budget_s is not None and clock() - t0 > budget_s:
            break
    return done, clock() - t0, None


def pool_break_impulse2d(
    n_worlds: int = 1,
    steps: int = 1200,
    substeps: int = POOL_SUBSTEPS,
    sleeping: bool = True,
    *,
    budget_s: float | None = None,
    cue_y_offsets: np.ndarray | None = None,
) -> dict:
    """Time ``n_worlds`` impulse2d pool-break worlds, stepped as one batch, for ``steps`` steps
    (one ``World.step`` call a step; see :func:`pool_batch_world` for ``cue_y_offsets``).

    A warm-up step runs first on a separate world (a batch of two for a batch run), so
    first-call costs stay out of the timing; the timed world starts fresh, as in pymunk.
    With ``budget_s``, stepping stops once that much time has passed (a prefix of the break
    is timed); ``steps`` in the result says how many steps were done.

    Returns ``world_steps_per_s``, ``seconds``, ``steps``, ``step_us`` (duration of every
    step, single world only, else None), ``final_positions`` of world 0 (n_balls, 2),
    ``final_batch`` (n_balls, n_worlds, 2; batch only, else None), ``worlds_identical``
    (every world of the batch ends exactly as world 0), ``finite`` (every world) and
    ``threads`` (``World.threads`` of the timed world).
    """
    dt = pool_break().dt
    warm, _ = pool_batch_world(2 if n_worlds > 1 else 1, substeps, sleeping)
    warm.step(dt)
    world, balls = pool_batch_world(n_worlds, substeps, sleeping, cue_y_offsets)
    done, seconds, step_us = _timed_steps(world, dt, steps, budget_s)

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
        "threads": world.threads,
    }


def pool_break_one_call(
    steps: int = 1200, substeps: int = POOL_SUBSTEPS, sleeping: bool = True, *, repeats: int = 5
) -> dict:
    """Time the single-world pool break run in one compiled call, ``World.step(dt,
    steps=steps)``, on ``repeats`` fresh worlds after a warm-up call on another; the run of
    median time. Returns ``world_steps_per_s``, ``seconds``, ``steps``, ``final_positions``
    and ``repeats_identical`` (every repeat ended in the same state)."""
    dt = pool_break().dt
    warm, _ = pool_batch_world(1, substeps, sleeping)
    warm.step(dt, steps=2)
    runs = []
    for _ in range(repeats):
        world, balls = pool_batch_world(1, substeps, sleeping)
        t0 = time.perf_counter()
        world.step(dt, steps=steps)
        runs.append((time.perf_counter() - t0, _positions(world, balls)))
    seconds, final = sorted(runs, key=lambda r: r[0])[repeats // 2]
    return {
        "world_steps_per_s": steps / seconds,
        "seconds": seconds,
        "steps": steps,
        "final_positions": final,
        "repeats_identical": all(np.array_equal(r[1], runs[0][1]) for r in runs),
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
            c = world.contacts()
            if c.size:
                on_cushion = np.isin(c.slot_a, cushion_slots) | np.isin(c.slot_b, cushion_slots)
                touched = bool(np.any(on_cushion & (c.impulse > 0.0)))
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
    try:  # pymunk only here: the rest of this module runs without it (bench_gpu.py)
        from bench import pymunk_peer
    except ImportError:
        import pymunk_peer
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


def large_pyramid_impulse2d(steps: int | None = None, budget_s: float | None = None) -> dict:
    """Box2D v3's ``large_pyramid`` benchmark (:func:`scenes.large_pyramid`, 5,050 boxes) in
    impulse2d: step it ``steps`` times (default the scene's 500), timing from the first
    step, and measure how far it has settled (:func:`scenes.pyramid_settling`).

    Mirrors :func:`box2d_peer.large_pyramid_box2d`. A warm-up step runs first on a small
    pyramid, so compiling stays out of the timing; the big world's own first-step costs
    (its scratch growing) stay in, as they do in Box2D's. With ``budget_s`` the timing
    stops once that much time has passed and the rest of the steps run untimed, so the
    settling is always measured after ``steps`` steps.

    Returns ``ms_per_step`` (over the timed steps), ``timed_steps``, ``steps``,
    ``median_step_ms`` (of the timed steps), ``build_s`` (building the world, untimed) and
    the measures of :func:`scenes.pyramid_settling`.
    """
    scene = large_pyramid()
    validate(scene)
    steps = scene.steps if steps is None else steps
    warm, _ = _pyramid_world(pyramid(4))
    warm.step(scene.dt)
    t0 = time.perf_counter()
    world, boxes = _pyramid_world(scene)
    build_s = time.perf_counter() - t0

    step, dt, clock = world.step, scene.dt, time.perf_counter
    stamps = [clock()]
    for _ in _progress(range(steps), steps, "impulse2d large_pyramid"):
        step(dt)
        if budget_s is None or stamps[-1] - stamps[0] <= budget_s:
            stamps.append(clock())
    timed = len(stamps) - 1
    step_ms = 1e3 * np.diff(stamps)
    return {
        "ms_per_step": float(step_ms.mean()),
        "median_step_ms": float(np.median(step_ms)),
        "timed_steps": timed,
        "steps": steps,
        "build_s": build_s,
        **pyramid_settling(scene, _positions(world, boxes)),
    }


# -- rain ------------------------------------------------------------------------------------
def _rain_world(scene: Rain, sleeping: bool = RAIN_SLEEPING) -> tuple[p2.World, list[int]]:
    """The rain scene in impulse2d (ground: a plane at y = 0); returns the world and the
    ``bodies`` indices of the falling bodies in scene order."""
    world = p2.World(gravity=scene.gravity, sleeping=sleeping)  # default substeps
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


def settled_rain_impulse2d(count: int, steps: int = 120, settle_steps: int = 600) -> dict:
    """The rain with sleeping on (``World`` defaults: 0.5 s below 0.05 m/s), as
    ``box2d_peer.settled_rain_box2d``: ``ms_per_step`` after ``settle_steps`` untimed
    steps, ``awake`` (bodies awake at the end) and ``finite``."""
    scene = rain(count)
    world, bodies = _rain_world(scene, sleeping=True)
    step, dt = world.step, scene.dt
    for _ in _progress(range(settle_steps), settle_steps, f"impulse2d rain {count} settling"):
        step(dt)
    t0 = time.perf_counter()
    for _ in range(steps):
        step(dt)
    seconds = time.perf_counter() - t0
    objects = world.bodies
    return {
        "ms_per_step": 1000 * seconds / steps,
        "awake": sum(bool(objects[i].awake) for i in bodies),
        "finite": bool(np.all(np.isfinite(_positions(world, bodies)))),
    }
