"""What each stage of a substep costs, plain order against coloured, on a captured step.

The step is ``bench/solver_probe.py``'s capture (the 20-row pyramid's 101st step, or
``--scene large``: Box2D's ``large_pyramid`` after 20 steps; ``--scene pool``: the break's
11th; ``--scene rain``: the 1,000-body rain after its 60 untimed steps; ``--scene smash`` or
``many_pyramids``: Box2D's, at full size, as ``profile_step.py --box2d`` takes them), its points as
the contact preparation leaves them. Each stage's kernel is called
``--repeats`` times on the same arrays (the state drifts; the work does not) and the
median of five such calls is reported in ns a contact point a call. The plain rows run
the engine's solver with nothing coloured, the coloured rows with the world's manifolds
coloured and packed as ``pipeline.colour`` does once a step.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numba
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))  # bench/: the probe, the scenes
import solver_probe
from engine_runs import _pyramid_world
from impulse2d.core import colouring, contacts, context, integrate, lanes, solver
from impulse2d.core.workspace import STATE_F, colour_scratch
from profile_step import _case, box2d_case, rain_case
from report import fmt, print_table
from scenes import large_pyramid


def _large():
    scene = large_pyramid()
    world, _ = _pyramid_world(scene)
    return _case("large_pyramid, after 20 steps", world, scene.dt, 20)


solver_probe.SCENES["large"] = _large
solver_probe.SCENES["rain"] = lambda: rain_case(1000)
for _name in ("smash", "many_pyramids"):  # Box2D's, at full size (profile_step.box2d_case)
    solver_probe.SCENES[_name] = lambda name=_name: box2d_case(name)


@numba.njit(nogil=True)
def _colour(terms, points, ids, n, floats, ints, repeats):
    c = colouring.colour_arrays(floats, ints)
    count = 0
    for _ in range(repeats):
        count = colouring.colour_manifolds(terms, points, ids, n, c.masks, c.found, c.colours,
                                           c.order, c.starts, c.others)  # fmt: skip
        colouring.pair_bodies(ids, c.order, count, c.body_a, c.body_b)
    return count


@numba.njit(nogil=True)
def _pack(points, floats, ints, count, threshold, repeats):
    c = colouring.colour_arrays(floats, ints)
    for _ in range(repeats):
        colouring.pack(points, c.order, count, c.con, threshold)


@numba.njit(nogil=True)
def _sweep(body, ctx, terms, points, ids, n, biased, floats, ints, rest, repeats):
    values = (ctx[context.INV_H], ctx[context.PUSH_SPEED], biased)
    states = np.zeros((terms.shape[0], STATE_F))
    moving = np.zeros(terms.shape[0], np.int64)
    count = integrate.list_moving(terms, moving)
    others = colouring.colour_arrays(floats, ints).others if rest < n else ints[:0]
    if rest < n:
        lanes.load_states(body, 0, terms, states)
    for _ in range(repeats):
        if rest < n:  # as pipeline.substeps: the body states loaded, solved, stored
            lanes.load_moving(body, 0, terms, states, moving, count)
            lanes.solve_coloured(states, values, floats, ints)
            lanes.store_states(body, 0, states, moving, count)
        solver.sweep(body, 0, ctx, terms, points, ids, n, biased, False, rest, others)


@numba.njit(nogil=True)
def _warm(body, points, ids, n, repeats):
    for _ in range(repeats):
        solver.warm_start(body, 0, points, ids, n, np.zeros(0, np.int64))


@numba.njit(nogil=True)
def _warm_coloured(body, terms, floats, ints, count, repeats):
    states = np.zeros((terms.shape[0], STATE_F))
    lanes.load_states(body, 0, terms, states)
    for _ in range(repeats):  # (in the engine, between the loading and the solve pass)
        lanes.warm_start_coloured(states, floats, ints, count)


@numba.njit(nogil=True)
def _follow(body, ctx, terms, points, ids, n, repeats):
    for _ in range(repeats):
        contacts.follow_bodies(body, 0, ctx, terms, points, ids, n, np.zeros(0, np.int64))


@numba.njit(nogil=True)
def _follow_coloured(body, floats, ints, count, repeats):
    for _ in range(repeats):
        lanes.follow_coloured(body, 0, floats, ints, count)


def _ns(call, repeats: int, points: int) -> float:
    call(1)  # compiles
    times = []
    for _ in range(5):
        t0 = time.perf_counter()
        call(repeats)
        times.append(time.perf_counter() - t0)
    return statistics.median(times) / repeats / points * 1e9


def run(scene: str, repeats: int) -> tuple[int, int, list[tuple[str, float]]]:
    cap = solver_probe.capture(scene)
    n, body, terms, ids, ctx = cap["n"], cap["body"], cap["terms"], cap["ids"], cap["ctx"]
    plain_points, points = cap["points"].copy(), cap["points"].copy()
    floats, ints = colour_scratch(terms.shape[0], n)
    count = _colour(terms, points, ids, n, floats, ints, 1)
    threshold = ctx[context.RESTITUTION_THRESHOLD]
    _pack(points, floats, ints, count, threshold, 1)
    rest = n - 2 * count
    rows = [
        ("solve pass, plain order", lambda r: _sweep(body, ctx, terms, plain_points, ids, n,
                                                      True, floats, ints, n, r)),
        ("solve pass, coloured", lambda r: _sweep(body, ctx, terms, points, ids, n, True,
                                                  floats, ints, rest, r)),
        ("relax pass, plain order", lambda r: _sweep(body, ctx, terms, plain_points, ids, n,
                                                      False, floats, ints, n, r)),
        ("relax pass, coloured", lambda r: _sweep(body, ctx, terms, points, ids, n, False,
                                                  floats, ints, rest, r)),
        ("warm start, plain order", lambda r: _warm(body, plain_points, ids, n, r)),
        ("warm start, coloured", lambda r: _warm_coloured(body, terms, floats, ints, count, r)),
        ("anchors follow, plain order", lambda r: _follow(body, ctx, terms, plain_points, ids,
                                                          n, r)),
        ("anchors follow, coloured", lambda r: _follow_coloured(body, floats, ints, count, r)),
        ("colouring (once a step)", lambda r: _colour(terms, points, ids, n, floats, ints, r)),
        ("packing (once a step)", lambda r: _pack(points, floats, ints, count, threshold, r)),
    ]  # fmt: skip
    return n, count, [(name, _ns(call, repeats, n)) for name, call in rows]


REPEATS = {"pyramid": 200, "large": 5, "pool": 2000, "rain": 20, "smash": 3, "many_pyramids": 2}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", choices=list(REPEATS), default="pyramid")
    parser.add_argument("--repeats", type=int, default=0, help="calls a timing (0: by scene)")
    parser.add_argument("--quick", action="store_true", help="a few calls: a smoke test")
    args = parser.parse_args()
    repeats = args.repeats or REPEATS[args.scene]
    repeats = 2 if args.quick else repeats
    n, count, rows = run(args.scene, repeats)
    print(f"{args.scene}: {n} points, {count} manifolds coloured; numba {numba.__version__}, "
          f"median of 5 timings of {repeats} calls")  # fmt: skip
    print_table(("stage", "ns a point a call"), ("<", ">"), [(r, fmt(ns)) for r, ns in rows])


if __name__ == "__main__":
    main()
