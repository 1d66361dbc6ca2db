"""The contact solve's data layout, measured before the port: ns a point a pass.

Box2D v3 solves contacts over compact arrays: a 32-byte body state (velocity, angular
velocity, position and rotation deltas over the step), constraints prepared once a step
into a structure of arrays of two-point manifolds, and a graph colouring so that the
constraints of one colour share no dynamic body and are solved side by side in SIMD lanes.
impulse2d's solver (``core.solver.sweep``) walks 35-float64 point rows and 30-float64 body
rows in order, one point at a time. This probe times the pass that matters most, the
biased solve of a substep (normals, then friction within the cone), on the contacts of a
real step: Box2D's 20-row pyramid (210 boxes) after 100 steps, copied out of
``pipeline.step_world`` just before its substeps (``profile_step``'s kernel, its stages up to
the colouring and packing).

Kernels (``bench/solver_probe_kernels.py``); each runs ``--passes`` passes over the same
constraints, and the figure is the median of ``--rounds`` timed calls over points x passes:

* ``today``: ``core.solver.sweep`` on the step's point rows (with the two-point block
  solve it does for every pair, and its pass over the pairs against planes);
* ``compact``: the compact layout in the narrowphase's order, the body states read and
  written in place (Gauss-Seidel as today);
* ``coloured``: the manifolds sorted by colour (greedy; the bodies that cannot move, one
  dummy row, shared freely); per colour a gather loop copies the two bodies' states into
  lane arrays, a loop solves the lanes, a scatter loop writes the velocities back;
* ``coloured, blocks of 4``: the same with each colour padded to a multiple of four and
  solved four lanes at a time, loads before stores (what an SLP vectoriser packs);
* ``coloured, lane loop vectorised``: the lane loop written so that LLVM's loop
  vectoriser takes it (``solver_probe_kernels.solve_vector``), bitwise the same lanes;
* ``coloured, block solve by selects``: the lanes with each manifold's two normals solved
  together as ``core.solver.solve_pair_normals`` does (today's answer to
  ``large_pyramid``'s creep), every case computed and the first that holds selected, so
  the lane loop stays free of branches; lane by lane and vectorised (float64);
* ``floor``: the soft normal impulse alone over gathered arrays, one array a field: the
  arithmetic a vectorised loop costs, for scale;

in float64 and float32. "packed ymm/zmm" counts the 256- and 512-bit packed floating-point
instructions in the kernel's machine code (``inspect_asm``): the ones above a handful
mean numba/LLVM vectorised a loop. "ground J / (m g h)" checks the physics: the normal
impulse on the ground over the pyramid's weight times the substep (about 1 in every layout:
Gauss-Seidel in another order converges to the same answer, not to the same bits).
Rerun with ``NUMBA_SLP_VECTORIZE=1`` (numba's SLP vectoriser, off by default) and
``NUMBA_LOOP_VECTORIZE=0`` to see what each vectoriser does.

``--scene pool`` takes the 16-ball pool break's 11th step instead (one-point contacts,
tens of them: the small world where colouring may not pay). The last line gives what
colouring costs a step (greedy colours, then the manifolds sorted into colour order).

Run: ``python bench/solver_probe.py`` (about 40 s, most of it compiling); ``--quick``.
"""

from __future__ import annotations

import argparse
import re
import statistics
import time

import llvmlite.binding
import numba
import numpy as np

from impulse2d.core import context, solver
from impulse2d.core.colouring import colour_arrays, colour_step, unpack_step
from impulse2d.core.integrate import list_moving
from impulse2d.core.lanes import load_moving, load_states, solve_coloured, store_states
from impulse2d.core.state import INV_MASS
from impulse2d.core.workspace import (
    AGAINST_PLANE,
    IN_COLOUR,
    NORMAL_J,
    NORMAL_MASS,
    SEP0,
    STATE_F,
    Workspace,
    colour_scratch,
    views,
)

try:
    from bench import solver_probe_kernels as kernels
    from bench.profile_step import STAGES, _arrays, _stages, pool_single_case, pyramid_case
    from bench.report import fmt, print_table
    from bench.solver_probe_kernels import LANE_F, body_states, colour, manifolds, pad_colours
except ImportError:
    import solver_probe_kernels as kernels
    from profile_step import STAGES, _arrays, _stages, pool_single_case, pyramid_case
    from report import fmt, print_table
    from solver_probe_kernels import LANE_F, body_states, colour, manifolds, pad_colours


@numba.njit(nogil=True)
def today(body, ctx, terms, points, ids, n, passes):
    """``passes`` biased sweeps of the engine's plain-order solver over world 0's points
    (nothing coloured: every point left to the sweep)."""
    for _ in range(passes):
        solver.sweep(body, 0, ctx, terms, points, ids, n, True, False, n, np.zeros(0, np.int64))


@numba.njit(nogil=True)
def engine_coloured(body, ctx, terms, points, ids, n, passes, floats, ints):
    """``passes`` biased passes of the engine's solver with the world coloured (what
    ``pipeline.colour`` does once a step, then ``lanes.solve_coloured`` and the sweep
    of what is left; ``floats``, ``ints``: ``workspace.colour_scratch``)."""
    count = colour_step(terms, points, ids, n, floats, ints, ctx[context.RESTITUTION_THRESHOLD])
    values = (ctx[context.INV_H], ctx[context.PUSH_SPEED], True)
    states = np.zeros((terms.shape[0], STATE_F))
    moving = np.zeros(terms.shape[0], np.int64)
    moving_count = list_moving(terms, moving)
    others = colour_arrays(floats, ints).others
    load_states(body, 0, terms, states)
    for _ in range(passes):  # as pipeline.substeps: the states loaded, solved, stored
        load_moving(body, 0, terms, states, moving, moving_count)
        solve_coloured(states, values, floats, ints)
        store_states(body, 0, states, moving, moving_count)
        solver.sweep(body, 0, ctx, terms, points, ids, n, True, False, n - 2 * count, others)
    unpack_step(points, floats, ints, count)


# What --scene captures: the pyramid's 101st step (settled, every contact resting) and the
# pool break's 11th (the rack still together, 30 contacts).
SCENES = {
    "pyramid": lambda: pyramid_case(20, 100),
    "pool": lambda: pool_single_case(10),
}


SCENES_SAID = {"pyramid": "20 rows, step 101", "pool": "16-ball break, step 11"}
BEFORE_SUBSTEPS = STAGES.index("colouring and packing") + 1  # profile_step's stages to run


def capture(scene: str = "pyramid") -> dict:
    """The prepared contact points of the scene's captured step (``SCENES``), and its bodies."""
    case = SCENES[scene]()
    state = tuple(a.copy() for a in _arrays(case.saved))
    caps = case.caps
    space = Workspace(1, case.saved.body.shape[1], int(caps[0]), int(caps[1]))
    ctx = case.world.settings.step_context(case.dt)
    n = _stages(state, case.world.layout.rows, ctx, 0, space.floats[0], space.ints[0],
                int(caps[0]), int(caps[1]), BEFORE_SUBSTEPS)  # fmt: skip
    scratch = views(space.floats[0], space.ints[0], state[0].shape[1], int(caps[0]), int(caps[1]))
    points = scratch.points[:n].copy()
    points[points[:, AGAINST_PLANE] == IN_COLOUR, AGAINST_PLANE] = 0.0  # as the narrowphase
    # left them: every layout starts from there
    return {
        "n": n,
        "body": state[0],
        "terms": scratch.terms.copy(),
        "points": points,
        "ids": scratch.point_ids[:n].copy(),
        "ctx": ctx,
        "movable": case.world.state.body[0, :, INV_MASS] > 0.0,
    }


_PACKED = re.compile(r"^\s*v\w*p[sd]\s.*%[yz]mm", re.MULTILINE)


def packed_instructions(*compiled) -> int:
    """Packed 256/512-bit floating-point instructions in the kernels' machine code."""
    return sum(len(_PACKED.findall(asm)) for k in compiled for asm in k.inspect_asm().values())


def timed(call, rounds: int) -> float:
    """The median seconds of ``rounds`` calls, after one that compiles."""
    call()
    times = []
    for _ in range(rounds):
        t0 = time.perf_counter()
        call()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


class Scene:
    """The captured step in every layout the kernels take."""

    def __init__(self, name: str = "pyramid") -> None:
        self.cap = cap = capture(name)
        self.n, ctx = cap["n"], cap["ctx"]
        self.inv_h, self.push = ctx[context.INV_H], ctx[context.PUSH_SPEED]
        self.con, self.pair = manifolds(cap)
        self.dummy = cap["body"].shape[1]
        colours = colour(self.pair, self.dummy)
        self.order = np.argsort(colours, kind="stable")
        self.starts = np.searchsorted(colours[self.order], np.arange(colours.max() + 2))
        # the pyramid's weight over a substep (the pool table has no ground: nan)
        weight = float(cap["movable"].sum()) * 9.81 * ctx[context.H]
        self.weight_impulse = weight if name == "pyramid" else float("nan")

    def consts(self, dtype) -> np.ndarray:
        """The kernels' ``consts`` (``solver_probe_kernels.INV_H`` ...) in ``dtype``."""
        return np.array([self.inv_h, self.push, 0.0, 1.0], dtype)

    def coloured_args(self, dtype, passes: int, how: int) -> tuple:
        """``solver_probe_kernels.coloured``'s arguments for solving the lanes ``how``."""
        con, pair = self.con[:, self.order], self.pair[self.order]
        starts = self.starts.astype(np.int64)
        if how == kernels.BLOCKS_OF_FOUR:
            con, pair, starts = pad_colours(con, pair, starts, 4, self.dummy)
        con = np.ascontiguousarray(con).astype(dtype)
        lanes = np.zeros((LANE_F, con.shape[1]), dtype)
        states = body_states(self.cap, dtype)
        return states, con, pair, starts, lanes, self.consts(dtype), passes, how


def _row(name, seconds, scene, passes, packed, ground) -> tuple[str, float, int, float]:
    return name, seconds / (scene.n * passes) * 1e9, packed, ground


def colouring_ns(scene: Scene, rounds: int) -> float:
    """ns a point of colouring a step's manifolds and sorting them into colour order."""
    con, pair = scene.con, scene.pair
    out = (np.zeros(pair.shape[0], np.int64), np.empty_like(con), np.empty_like(pair),
           np.zeros(65, np.int64))  # fmt: skip
    repeats = 200

    def call():
        for _ in range(repeats):
            kernels.colour_and_sort(con, pair, scene.dummy, *out)

    return timed(call, rounds) / (repeats * scene.n) * 1e9


def run(passes: int, rounds: int, name: str = "pyramid") -> tuple[list[tuple], Scene]:
    scene = Scene(name)
    cap, n = scene.cap, scene.n
    body, points = cap["body"].copy(), cap["points"].copy()
    seconds = timed(lambda: today(body, cap["ctx"], cap["terms"], points, cap["ids"], n, passes),
                    rounds)  # fmt: skip
    ground = points[:, NORMAL_J][cap["ids"][:, 0] == 0].sum() / scene.weight_impulse
    rows = [_row("plain order: core.solver.sweep, float64 rows", seconds, scene, passes,
                 packed_instructions(today), ground)]  # fmt: skip
    body, points = cap["body"].copy(), cap["points"].copy()
    scratch = colour_scratch(cap["terms"].shape[0], n)
    call = lambda: engine_coloured(body, cap["ctx"], cap["terms"], points, cap["ids"], n, passes,  # noqa: E731
                                   *scratch)  # fmt: skip
    seconds = timed(call, rounds)
    ground = points[:, NORMAL_J][cap["ids"][:, 0] == 0].sum() / scene.weight_impulse
    rows.append(_row("engine, coloured: core.solver.sweep with core.lanes", seconds, scene,
                     passes, packed_instructions(engine_coloured), ground))  # fmt: skip
    for dtype in (np.float64, np.float32):
        name = np.dtype(dtype).name
        for block in (False, True) if dtype == np.float64 else (False,):
            kernel = kernels.compact_block if block else kernels.compact
            con = scene.con.astype(dtype)
            args = (body_states(cap, dtype), con, scene.pair, scene.consts(dtype), passes)
            seconds = timed(lambda args=args, kernel=kernel: kernel(*args), rounds)
            ground = kernels.ground_share(con, scene.pair, scene.dummy, scene.weight_impulse)
            label = f"compact, narrowphase order{', block solve' * block}, {name}"
            packed = packed_instructions(kernel)
            rows.append(_row(label, seconds, scene, passes, packed, ground))
        for how, solve, label in (
            (kernels.LANE_BY_LANE, kernels.solve_lanes, ""),
            (kernels.BLOCKS_OF_FOUR, kernels.solve_blocks, ", blocks of 4"),
            (kernels.VECTOR, kernels.solve_vector, ", lane loop vectorised"),
        ):
            args = scene.coloured_args(dtype, passes, how)
            seconds = timed(lambda args=args: kernels.coloured(*args), rounds)
            ground = kernels.ground_share(args[1], args[2], scene.dummy, scene.weight_impulse)
            label = f"coloured ({scene.starts.size - 1} colours){label}, {name}"
            packed = packed_instructions(solve)
            rows.append(_row(label, seconds, scene, passes, packed, ground))
        for vector in (False, True) if dtype == np.float64 else ():
            args = (*scene.coloured_args(dtype, passes, kernels.LANE_BY_LANE)[:-1], vector)
            seconds = timed(lambda args=args: kernels.coloured_block(*args), rounds)
            ground = kernels.ground_share(args[1], args[2], scene.dummy, scene.weight_impulse)
            solve = kernels.solve_vector_block if vector else kernels.solve_lanes_block
            how = "lane loop vectorised" if vector else "lane by lane"
            label = f"coloured, block solve by selects, {how}, {name}"
            rows.append(_row(label, seconds, scene, passes, packed_instructions(solve), ground))
        va, vb = np.zeros(n, dtype), np.zeros(n, dtype)
        acc, mass, sep = (points[:, col].astype(dtype) for col in (NORMAL_J, NORMAL_MASS, SEP0))
        args = (va, vb, acc, mass, sep, scene.consts(dtype), passes)
        seconds = timed(lambda args=args: kernels.normals_only(*args), rounds)
        rows.append(_row(f"floor: normals only, gathered, {name}", seconds, scene, passes,
                         packed_instructions(kernels.normals_only), float("nan")))  # fmt: skip
    return rows, scene


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--passes", type=int, default=400)
    parser.add_argument("--rounds", type=int, default=9)
    parser.add_argument("--scene", choices=list(SCENES), default="pyramid")
    parser.add_argument("--quick", action="store_true", help="a few passes: a smoke test")
    args = parser.parse_args()
    passes, rounds = (4, 2) if args.quick else (args.passes, args.rounds)
    flags = f"SLP vectoriser {'on' if numba.config.SLP_VECTORIZE else 'off'}, loop vectoriser "
    flags += "on" if numba.config.LOOP_VECTORIZE else "off"
    target = numba.config.CPU_NAME or llvmlite.binding.get_host_cpu_name()
    if numba.config.CPU_FEATURES is not None:
        target += f" [{numba.config.CPU_FEATURES}]"
    print(f"numba {numba.__version__}, code for {target} ({flags}); "
          f"{args.scene} ({SCENES_SAID[args.scene]}), {passes} passes, "
          f"median of {rounds}")  # fmt: skip
    rows, scene = run(passes, rounds, args.scene)
    base = rows[0][1]
    header = ("kernel", "ns a point a pass", "vs plain order", "packed ymm/zmm",
              "ground J / (m g h)")  # fmt: skip
    table = [(name, fmt(ns), fmt(ns / base), str(packed), fmt(ground))
             for name, ns, packed, ground in rows]  # fmt: skip
    print_table(header, ("<", ">", ">", ">", ">"), table)
    print(f"{scene.n} points in {scene.pair.shape[0]} manifolds, {scene.starts.size - 1} colours; "
          f"colouring them and sorting into colour order: {fmt(colouring_ns(scene, rounds))} ns "
          "a point, once a step (a step has two passes a substep)")  # fmt: skip


if __name__ == "__main__":
    main()
