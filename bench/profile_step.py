"""Where one compiled step spends its time: a per-stage profile of ``pipeline.step_world``.

cProfile sees a compiled call as one opaque line, so this profiles the step from inside:
a numba kernel runs the stages of ``step_world`` *cumulatively* (stage 1 only, stages 1-2,
..., all of them) over the worlds of a state copied mid-scene, and the difference between
two consecutive variants is a stage's own cost. The stages, in the step's order:

1. body terms (``integrate.step_terms``; with the at-rest test before it)
2. broadphase (``broadphase.find_pairs``)
3. narrowphase (``narrowphase.find_points``)
4. waking (``sleep.wake_touched``; when something wakes, the step looks again: body
   terms, broadphase and narrowphase once more, which this stage is charged with)
5. warm-start lookup (``contacts.count_dormant``, the spring stability test when the
   world has springs, ``contacts.carry_impulses``)
6. contact preparation (``contacts.prepare``)
7. colouring and packing (``pipeline.colour``; nothing below ``COLOUR_FROM`` points)
8. substeps (``pipeline.substeps``: integration, warm start, solve, relax; restitution)
9. projection (``projection.project_out_of_planes``)
10. finish (``pipeline.finish``: store contacts, events, forces, sleep, sensors, clock;
    ``refusal.leaves_envelope``)

A world at rest takes ``pipeline.rest_step`` in the full variant only. Before every
timed repeat the kernel restores each world from the copy (variant 0 does only that, and
its time is subtracted from the others), so every repeat times the same step. The full
variant is checked bitwise against ``World.step`` from the same state.

Scenes: the 1,024-world pool batch with varied shots (``scenes.pool_cue_offsets``) and a
single pool world, both after 100 steps of the break (the rack is breaking up, most
balls moving); the 20-row pyramid after 100 steps; the 4,000-body rain after its 60
untimed steps (mid-fall), all with ``bench_engine``'s settings. The batch runs in a
``numba.njit(parallel=True)`` kernel whose ``numba.prange`` goes over the worlds, on one
thread (``numba.set_num_threads(1)``): the figures are per world-step on one core.
(``Runner`` steps a batch as chunks of plain loops, ``pipeline.advance``, on Python
threads; the header gives the plain loop's figure for the full step beside the parallel
loop's.) A single world runs in a plain ``numba.njit`` kernel, as ``Runner`` steps one
world. Scratch memory is one row of ``workspace.Workspace(1, bodies, contact_capacity,
pair_capacity)`` cut by ``workspace.views``, with the capacities the world's runner had
grown to after stepping the scene.

The "World.step of the same step" figures in the headers are a Python call of
``World.step`` from the same state: they add the cost of the call (Python, and for a
batch the launch of the threads) to the compiled step's.

Run ``python bench/profile_step.py`` (about 20 seconds on 2 cores, most of it compiling the
two kernels; ``--quick`` for 64 worlds and a rain of 1,000) or ``python
bench/bench_engine.py --profile``.
``--box2d many_pyramids smash`` profiles Box2D's scenes (``box2d_scenes.py``) instead, one
world each at Box2D's size, after ``BOX2D_STEPS`` steps (a minute or two each: building
the scene and the untimed steps).
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass

import numba
import numpy as np

import impulse2d as p2
from impulse2d.core import context, pipeline
from impulse2d.core._jit import borrowed
from impulse2d.core.broadphase import find_pairs
from impulse2d.core.contacts import carry_impulses, count_dormant, prepare
from impulse2d.core.integrate import list_moving, spring_stability, step_terms
from impulse2d.core.narrowphase import find_points
from impulse2d.core.projection import project_out_of_planes
from impulse2d.core.refusal import leaves_envelope
from impulse2d.core.runner import available_threads
from impulse2d.core.sleep import wake_touched
from impulse2d.core.state import AWAKE, DYNAMIC, ENABLED, PLANE, WorldState
from impulse2d.core.workspace import Workspace, views
from impulse2d.world import Snapshot

try:  # imported as part of the repo (``bench.profile_step``) ...
    from bench import box2d_scenes
    from bench.engine_runs import (
        POOL_SUBSTEPS,
        _pool_world,
        _pyramid_world,
        _rain_world,
        pool_batch_world,
    )
    from bench.report import fmt, print_table
    from bench.scenes import pool_break, pool_cue_offsets, pyramid, rain
except ImportError:  # ... or run as a script, with bench/ on sys.path
    import box2d_scenes
    from engine_runs import (
        POOL_SUBSTEPS,
        _pool_world,
        _pyramid_world,
        _rain_world,
        pool_batch_world,
    )
    from report import fmt, print_table
    from scenes import pool_break, pool_cue_offsets, pyramid, rain

STAGES = (
    "body terms",
    "broadphase",
    "narrowphase",
    "waking",
    "warm-start lookup",
    "contact preparation",
    "colouring and packing",
    "substeps",
    "projection",
    "finish",
)
ALL = len(STAGES)
ROUNDS = 5  # timed calls of every variant, interleaved; the median is reported
TARGET_S = 0.05  # each timed call repeats the step about this long
NEEDS_ROOM = -1  # a stage found more pairs or points than the scratch row holds


# -- the kernels -------------------------------------------------------------------------------
@numba.njit(nogil=True)
def _restore(saved, state, w):
    """World ``w`` of ``state`` (a tuple of ``WorldState`` arrays) from ``saved``."""
    state[0][w] = saved[0][w]
    state[1][w] = saved[1][w]
    state[2][w] = saved[2][w]
    state[3][w] = saved[3][w]
    state[4][w] = saved[4][w]
    state[5][w] = saved[5][w]
    state[6][w] = saved[6][w]
    state[7][w] = saved[7][w]
    state[8][w] = saved[8][w]


@numba.njit(nogil=True)
def _collide(body, body_i, hull, shapes, w, ctx, scratch) -> int:
    """Broadphase and narrowphase once; the point count, or ``NEEDS_ROOM``."""
    terms, points, ids = scratch.terms, scratch.points, scratch.point_ids
    pairs, sorted_pairs, buckets = scratch.pairs, scratch.sorted_pairs, scratch.buckets
    n_pairs = find_pairs(body, body_i, shapes, w, ctx, terms, scratch.swept, pairs, sorted_pairs,
                         buckets)  # fmt: skip
    if n_pairs > pairs.shape[0]:
        return NEEDS_ROOM
    n = find_points(body, hull, shapes, w, ctx, terms, pairs, n_pairs, points, ids)
    return NEEDS_ROOM if n > points.shape[0] else n


@numba.njit(nogil=True)
def _stages(state, layout, ctx, w, floats, ints, points_cap, pairs_cap, stages) -> int:
    """The first ``stages`` stages of ``pipeline.step_world`` for world ``w``, in its
    order and with its calls; returns the step's contact points (0 before the
    narrowphase), or ``NEEDS_ROOM``. The arrays are ``borrowed``, as ``pipeline.advance``
    hands them to the stages."""
    body, body_i, spring, _, contact, contact_i, world_i, time, hull = state
    body, body_i, spring = borrowed(body), borrowed(body_i), borrowed(spring)
    hull = borrowed(hull)
    contact, contact_i, world_i = borrowed(contact), borrowed(contact_i), borrowed(world_i)
    time, layout, ctx = borrowed(time), borrowed(layout), borrowed(ctx)
    floats, ints = borrowed(floats), borrowed(ints)
    state = (body, body_i, spring, borrowed(state[3]), contact, contact_i, world_i, time, hull)
    scratch = views(floats, ints, body.shape[1], points_cap, pairs_cap)
    shapes, ends, sensors = pipeline.split_layout(layout, body.shape[1], spring.shape[1])
    if pipeline.at_rest(body_i, shapes, w):
        if stages == ALL:
            pipeline.rest_step(body, contact, world_i, time, w, ctx)
        return 0
    terms, points, ids, pairs = scratch.terms, scratch.points, scratch.point_ids, scratch.pairs
    step_terms(body, body_i, shapes, spring, ends, hull, w, ctx, terms)
    if stages < 2:
        return 0
    if stages == 2:
        n_pairs = find_pairs(
            body, body_i, shapes, w, ctx, terms, scratch.swept, pairs, scratch.sorted_pairs,
            scratch.buckets,
        )  # fmt: skip
        return NEEDS_ROOM if n_pairs > pairs.shape[0] else 0
    n = _collide(body, body_i, hull, shapes, w, ctx, scratch)
    if n < 0 or stages == 3:
        return n
    while wake_touched(body, body_i, shapes, spring, ends, w, terms, ids, n):
        step_terms(body, body_i, shapes, spring, ends, hull, w, ctx, terms)
        n = _collide(body, body_i, hull, shapes, w, ctx, scratch)
        if n < 0:
            return n
    if stages == 4:
        return n
    if n + count_dormant(body_i, contact_i, world_i, w, terms) > points.shape[0]:
        return NEEDS_ROOM
    if ends.shape[0]:
        spring_stability(body, body_i, spring, ends, w, terms, ctx[context.H])
    carry_impulses(contact, contact_i, world_i, w, terms, points, ids, n)
    if stages == 5:
        return n
    prepare(body, w, ctx, terms, points, ids, n)
    if stages == 6:
        return n
    coloured = pipeline.colour(ctx, scratch, n)
    if stages == 7:
        return n
    n_moving = list_moving(terms, scratch.moving)
    pipeline.substeps(body, body_i, spring, ends, w, ctx, scratch, n, coloured, n_moving)
    if stages == 8:
        return n
    project_out_of_planes(body, hull, shapes, w, points, ids, n)
    if stages == 9:
        return n
    pipeline.finish(state, shapes, ends, sensors, w, ctx, scratch, n, n_moving)
    leaves_envelope(body, body_i, shapes, w)
    return n


@numba.njit(nogil=True, parallel=True)
def run_parallel(saved, state, layout, ctx, floats, ints, caps, stages, repeats, points):
    """``repeats`` times: restore every world, then run ``stages`` stages in each, the
    worlds spread by ``numba.prange`` (over the threads numba is set to). ``points[w]``
    gets world ``w``'s contact points (or ``NEEDS_ROOM``); ``caps`` is (points, pairs)."""
    worlds = state[7].shape[0]
    for _ in range(repeats):
        for w in numba.prange(worlds):
            _restore(saved, state, w)
        if stages > 0:
            for w in numba.prange(worlds):
                points[w] = _stages(
                    state, layout, ctx, w, floats[0], ints[0], caps[0], caps[1], stages
                )


@numba.njit(nogil=True)
def run_plain(saved, state, layout, ctx, floats, ints, caps, stages, repeats, points):
    """``run_parallel`` as a plain loop over the worlds."""
    worlds = state[7].shape[0]
    for _ in range(repeats):
        for w in range(worlds):
            _restore(saved, state, w)
        if stages > 0:
            for w in range(worlds):
                points[w] = _stages(
                    state, layout, ctx, w, floats[0], ints[0], caps[0], caps[1], stages
                )


# -- the scenes --------------------------------------------------------------------------------
@dataclass
class Case:
    """A world stepped to the profiled moment, and what the kernels need to replay the
    next step: the state before it (``saved``) and after it (``after``, by ``World.step``)."""

    name: str
    world: p2.World
    dt: float
    snapshot: Snapshot  # the state before the step, with the grown capacities
    after: WorldState
    caps: np.ndarray  # (contact capacity, pair capacity), as the world's runner grew them

    @property
    def saved(self) -> WorldState:
        return self.snapshot.state


def _arrays(state: WorldState) -> tuple[np.ndarray, ...]:
    return tuple(state.arrays().values())


def _case(name: str, world: p2.World, dt: float, steps: int) -> Case:
    """Step ``world`` ``steps`` times, then once more (its runner grows the capacities
    that step needs) to record the reference; ``saved`` is the state in between, with
    the grown capacities."""
    if steps:
        world.step(dt, steps=steps)
    before = world.snapshot()
    world.step(dt)
    after = world.state.copy()
    world.restore(before)
    caps = np.array([world.state.contact_capacity, world._runner.pair_capacity], np.int64)
    return Case(name, world, dt, world.snapshot(), after, caps)


def pool_batch_case(worlds: int, steps: int = 100) -> Case:
    """The pool break with one shot per world (``pool_cue_offsets``), after ``steps``."""
    batch, _ = pool_batch_world(worlds, POOL_SUBSTEPS, True, pool_cue_offsets(worlds))
    name = f"pool break, varied shots, {worlds:,} worlds, after {steps} steps"
    return _case(name, batch, pool_break().dt, steps)


def pool_single_case(steps: int = 100) -> Case:
    scene = pool_break()
    world, _, _ = _pool_world(scene, POOL_SUBSTEPS, True)
    return _case(f"pool break, 1 world, after {steps} steps", world, scene.dt, steps)


def pyramid_case(base: int = 20, steps: int = 100) -> Case:
    scene = pyramid(base)
    world, _ = _pyramid_world(scene)
    return _case(f"pyramid base {base}, 1 world, after {steps} steps", world, scene.dt, steps)


# Box2D's scenes (``box2d_scenes``) profiled mid-scene: the steps before the profiled one
# (the pyramids settled on their grounds; the smash just after the heavy box hits).
BOX2D_STEPS = {"many_pyramids": 60, "smash": 150, "tumbler": 200, "spinner": 200,
               "joint_grid": 100}  # fmt: skip


def box2d_case(name: str) -> Case:
    """Box2D's benchmark scene ``name`` at its own size, after ``BOX2D_STEPS[name]``
    steps (``box2d_scenes.scenes``)."""
    sizes = box2d_scenes.Sizes()
    build = {row[0]: row[2] for row in box2d_scenes.scenes(sizes)}[name]
    world, drive = build()
    for _ in range(BOX2D_STEPS[name]):
        drive(world)
        world.step(box2d_scenes.DT)
    return _case(f"Box2D's {name}, 1 world", world, box2d_scenes.DT, 0)


def rain_case(count: int = 4000) -> Case:
    scene = rain(count)
    world, _ = _rain_world(scene)
    name = f"rain {count:,} bodies, 1 world, after {scene.settle_steps} steps"
    return _case(name, world, scene.dt, scene.settle_steps)


# -- measuring ---------------------------------------------------------------------------------
@dataclass
class Profile:
    """What :func:`profile` measured for a :class:`Case` (times in us per world-step)."""

    cumulative: list[float]  # after stages 1..ALL
    restore_us: float  # variant 0, subtracted from the others
    repeats: int  # steps per timed call and world
    points: float  # contact points per world-step
    matches: bool  # the full variant left the state World.step left, bitwise
    world_step_us: dict[int, float]  # World.step of the same step, by thread count
    plain_us: float | None  # the full step in the plain loop (a batch only)


Call = Callable[[int, int], float]


def _kernel_call(case: Case, kernel: Callable, state: tuple, points: np.ndarray) -> Call:
    """``call(stages, repeats)``: run ``kernel`` on the case, return the seconds."""
    saved = _arrays(case.saved)
    space = Workspace(1, case.saved.body.shape[1], int(case.caps[0]), int(case.caps[1]))
    layout, ctx = case.world.layout.rows, case.world.settings.step_context(case.dt)

    def call(stages: int, repeats: int) -> float:
        t0 = time.perf_counter()
        kernel(saved, state, layout, ctx, space.floats, space.ints, case.caps, stages, repeats,
               points)  # fmt: skip
        return time.perf_counter() - t0

    return call


def _medians(call: Call, variants: list[int], repeats: int, rounds: int) -> list[float]:
    """The median seconds of ``call(k, repeats)`` for each ``k``, the variants interleaved
    round by round (a busy spell on the shared machine slows them alike)."""
    times: list[list[float]] = [[] for _ in variants]
    for _ in range(rounds):
        for i, k in enumerate(variants):
            times[i].append(call(k, repeats))
    return [statistics.median(t) for t in times]


def _world_step_us(case: Case, threads: int, calls: int) -> float:
    """Median us per world-step of ``World.step`` from the case's state, on ``threads``."""
    world, old = case.world, case.world.threads
    world.threads = threads
    seconds = []
    try:
        for _ in range(calls):
            world.restore(case.snapshot)
            t0 = time.perf_counter()
            world.step(case.dt)
            seconds.append(time.perf_counter() - t0)
    finally:
        world.threads = old
        world.restore(case.snapshot)
    return 1e6 * statistics.median(seconds) / world.batch_size


def profile(case: Case, rounds: int = ROUNDS) -> Profile:
    """Time the cumulative variants of the case's next step (see the module docstring)."""
    batch = case.world.batch_size
    kernel = run_parallel if batch > 1 else run_plain
    state = tuple(a.copy() for a in _arrays(case.saved))
    points = np.zeros(batch, np.int64)
    call = _kernel_call(case, kernel, state, points)
    call(ALL, 1)  # compiles on first use
    if np.any(points == NEEDS_ROOM):
        raise RuntimeError(f"{case.name}: a world needed more room than its runner grew")
    matches = all(np.array_equal(a, b) for a, b in zip(state, _arrays(case.after), strict=True))
    mean_points = float(points.mean())
    repeats = max(1, round(TARGET_S / call(ALL, 1)))
    med = _medians(call, list(range(ALL + 1)), repeats, rounds)
    per = 1e6 / (repeats * batch)
    plain = None
    if batch > 1:
        plain_call = _kernel_call(case, run_plain, state, points)
        plain_call(0, 1)
        zero, full = _medians(plain_call, [0, ALL], repeats, rounds)
        plain = (full - zero) * per
    calls = max(rounds, min(2000, round(TARGET_S * 1e6 / max(med[ALL] * per * batch, 1.0))))
    threads = sorted({1, case.world.threads}) if batch > 1 else [1]
    return Profile(
        cumulative=[(m - med[0]) * per for m in med[1:]],
        restore_us=med[0] * per,
        repeats=repeats,
        points=mean_points,
        matches=matches,
        world_step_us={t: _world_step_us(case, t, calls) for t in threads},
        plain_us=plain,
    )


# -- report ------------------------------------------------------------------------------------
def _bodies(case: Case) -> tuple[int, float, float]:
    """Body slots, and per world the dynamic bodies and the awake ones (mean)."""
    shapes, body_i = case.world.layout.shapes, case.saved.body_i
    dynamic = (shapes[:, 1] == DYNAMIC) & (shapes[:, 0] != PLANE) & (body_i[:, :, ENABLED] == 1)
    awake = dynamic & (body_i[:, :, AWAKE] == 1)
    return shapes.shape[0], float(dynamic.sum(1).mean()), float(awake.sum(1).mean())


def report(case: Case, prof: Profile, rounds: int) -> None:
    """Print the case's header lines and its stage table."""
    batch = case.world.batch_size
    slots, dynamic, awake = _bodies(case)
    total = prof.cumulative[-1]
    print(f"\n{case.name}")
    print(
        f"  {batch:,} world{'s' if batch > 1 else ''} of {slots:,} body slots: {fmt(dynamic)} "
        f"dynamic bodies a world, {fmt(awake)} awake; {fmt(prof.points)} contact points a "
        f"world-step (capacities: {case.caps[0]:,} points, {case.caps[1]:,} pairs)"
    )
    kind = (
        "numba.njit(parallel=True) kernel, numba.prange over the worlds, 1 thread"
        if batch > 1
        else "plain numba.njit kernel"
    )
    print(
        f"  {kind}; {prof.repeats:,} repeat(s) a call, median of {rounds} calls; restoring the "
        f"state costs {fmt(prof.restore_us)} us a world (subtracted)"
    )
    steps = ", ".join(
        f"{fmt(us)} us/world-step on {t} thread{'s' if t > 1 else ''}"
        for t, us in prof.world_step_us.items()
    )
    line = f"  World.step of the same step (a Python call): {steps}"
    if prof.plain_us is not None:
        line += (
            f"; all stages in a plain loop over the worlds: {fmt(prof.plain_us)} us "
            f"(x{prof.plain_us / total:.2f} the prange loop's)"
        )
    print(line)
    print(f"  all stages == World.step, bitwise: {prof.matches}")
    rows, previous = [], 0.0
    for k, name in enumerate(STAGES):
        cum = prof.cumulative[k]
        own = cum - previous
        rows.append((f"{k + 1}. {name}", fmt(cum), fmt(own), f"{100 * own / total:.1f}"))
        previous = cum
    header = ("stage", "cumulative us/world-step", "own us", "share %")
    print_table(header, ("<", ">", ">", ">"), rows)


def run(
    worlds: int = 1024,
    quick: bool = False,
    stage: Callable[[str], None] | None = None,
    box2d: tuple[str, ...] = (),
):
    """Profile the four scenes and print their tables (``quick``: fewer worlds, a smaller
    rain, fewer rounds); with ``box2d``, those of Box2D's scenes instead."""
    say = stage or (lambda text: None)
    rounds = 3 if quick else ROUNDS
    print(
        f"per-stage profile of pipeline.step_world: cumulative variants, us per world-step; "
        f"{os.cpu_count()} CPUs, numba {numba.__version__}, threading layer "
        f"{numba.config.THREADING_LAYER}, {available_threads()} threads available; "
        f"load average {', '.join(f'{x:.2f}' for x in os.getloadavg())}"
    )
    builders = [
        lambda: pool_batch_case(worlds),
        pool_single_case,
        pyramid_case,
        lambda: rain_case(1000 if quick else 4000),
    ]
    if box2d:
        builders = [lambda name=name: box2d_case(name) for name in box2d]
    old = numba.get_num_threads()
    try:
        for build in builders:
            say("profile_step: building and stepping a scene")
            case = build()
            say(f"profile_step: {case.name}")
            numba.set_num_threads(1)
            prof = profile(case, rounds)
            numba.set_num_threads(old)
            report(case, prof, rounds)
    finally:
        numba.set_num_threads(old)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--worlds", type=int, default=1024, help="worlds of the pool batch")
    parser.add_argument("--quick", action="store_true", help="64 worlds, rain of 1,000")
    parser.add_argument("--no-progress", action="store_true", help="no progress output")
    parser.add_argument(
        "--box2d", nargs="+", choices=list(BOX2D_STEPS), default=(),
        help="profile these of Box2D's scenes (box2d_scenes.py) instead",
    )  # fmt: skip
    args = parser.parse_args(argv)
    if args.worlds < 2:
        parser.error(f"--worlds must be >= 2 (the single world is profiled too), got {args.worlds}")
    worlds = 64 if args.quick and args.worlds == 1024 else args.worlds

    def stage(text: str) -> None:
        if not args.no_progress:
            print(f"... {text}", file=sys.stderr, flush=True)

    run(worlds, args.quick, stage, tuple(args.box2d))


if __name__ == "__main__":
    main()
