"""The rows of the engine benchmark's table (``bench/bench_engine.py``), one function a section.

Each section runs impulse2d (``bench/engine_runs.py``) and pymunk (``bench/pymunk_peer.py``)
on one scene as the :class:`Plan` says, and appends its rows to the table: the pool break at
one world (a Python call of ``World.step`` a step, then the whole break in one compiled
call) and in a batch (and with one substep), the batch against the single world, the
pool-break checks, the varied-shot batch, the pyramids and the rain. The pyramids and the
rain also run in Box2D v3 (``bench/box2d_peer.py``), and a last section runs Box2D's own
``large_pyramid`` benchmark in impulse2d and Box2D only (pymunk: "-"). ``bench_engine.main``
calls them in that order and prints the table.

The issue's targets are checked in the notes of their rows ("target ...: ok" or "MISS"):
the single-world pool break at most 2x pymunk's time per world-step (stretch: faster than
pymunk), the 20-row pyramid at most 2x pymunk's ms/step with a top-box drift no worse than
pymunk's, the varied shots at 2 or more times pymunk's world-steps/s (impulse2d on its
default threads, pymunk in one process) and the 4,000-body rain no slower than pymunk.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import partial
from typing import Any

import numpy as np

try:  # imported as part of the repo (``bench.engine_rows``) ...
    from bench import box2d_peer, pymunk_peer
    from bench.engine_runs import (
        POOL_SUBSTEPS,
        _single_positions,
        _stage,
        large_pyramid_impulse2d,
        pool_break_impulse2d,
        pool_break_one_call,
        pool_check_impulse2d,
        pool_energy_pymunk,
        pyramid_impulse2d,
        rain_impulse2d,
        settled_rain_impulse2d,
    )
    from bench.report import fmt, ratio
    from bench.scenes import LATERAL_CREEP_M, PoolBreak, Rain, pool_cue_offsets
except ImportError:  # ... or run as a script, with bench/ on sys.path
    import box2d_peer
    import pymunk_peer
    from engine_runs import (
        POOL_SUBSTEPS,
        _single_positions,
        _stage,
        large_pyramid_impulse2d,
        pool_break_impulse2d,
        pool_break_one_call,
        pool_check_impulse2d,
        pool_energy_pymunk,
        pyramid_impulse2d,
        rain_impulse2d,
        settled_rain_impulse2d,
    )
    from report import fmt, ratio
    from scenes import LATERAL_CREEP_M, PoolBreak, Rain, pool_cue_offsets

# -- settings of the sections (the others are in bench_engine.py) ----------------------------
PYMUNK_SINGLE_REPEATS = 7  # single-world pymunk runs take milliseconds
PYRAMID_REPEATS = 3  # timed part of the pyramids, every engine
# The targets: ratios impulse2d / pymunk.
SINGLE_RATIO_TARGET = 2.0  # pool break, one world, us/world-step: at most (stretch: below 1)
PYRAMID_TARGET_BASE = 20
PYRAMID_RATIO_TARGET = 2.0  # its ms/step: at most; and its top drift at most pymunk's
VARIED_RATIO_TARGET = 2.0  # varied shots, world-steps/s: at least
RAIN_TARGET_COUNT = 4000
RAIN_RATIO_TARGET = 1.0  # its ms/step: at most

# One line of the table: scene, worlds, impulse2d, pymunk, ratio, notes; the rows Box2D runs
# in have two more cells before the notes, Box2D v3 and impulse2d / Box2D (see box2d_cells).
Row = tuple[str, ...]
Runs = dict[tuple[int, bool], dict]  # impulse2d's pool runs by (worlds, sleeping)


@dataclass(frozen=True)
class Plan:
    """What this run measures, from the command line (``--quick`` shortens everything)."""

    quick: bool
    budget: float  # seconds per impulse2d batch run
    positions: bool  # print the final ball positions
    scene: PoolBreak  # the pool break, validated
    threads: int  # World.threads of a batch (its default: every core numba sees)
    pool_steps: int
    n_worlds: int  # worlds in the batch runs
    single_repeats: int  # single-world impulse2d pool runs
    batch_repeats: int  # batch pool runs of each engine
    pyr_steps: int  # timed pyramid steps
    drift_steps: int  # pyramid steps before the drift is measured
    dt_pyr: float
    rain_counts: tuple[int, ...]
    rain_repeats: int
    rain_scene: Rain  # the smallest rain, for its description and step counts
    large_steps: int  # steps of the large_pyramid scene (0: not run)
    large_budget: float  # seconds of impulse2d's large_pyramid timed; the rest runs untimed


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


# -- table -----------------------------------------------------------------------------------
def _ok(flag: bool) -> str:
    return "ok" if flag else "MISS"


def _single_target(us_ratio: float) -> str:
    """The single-world target's verdict for a ratio of times per world-step."""
    return (
        f"target ratio <= {SINGLE_RATIO_TARGET:g}: {_ok(us_ratio <= SINGLE_RATIO_TARGET)}; "
        f"stretch < 1 (faster than pymunk): {_ok(us_ratio < 1.0)}"
    )


# -- pool break ------------------------------------------------------------------------------
def _steps_note(plan: Plan, r: dict) -> str:
    """How many steps a run timed (a batch run may stop at its budget)."""
    if r["steps"] < plan.pool_steps:
        return f"first {r['steps']} of {plan.pool_steps} steps (budget {plan.budget:g} s)"
    return f"{r['steps']} steps"


def _pool_rows(plan: Plan, imp: Runs, n: int, pm: dict) -> list[Row]:
    """Rate rows of the pool break at ``n`` worlds against pymunk's run ``pm``, sleeping on
    and off; at one world also the spread of the per-call times, and the target."""
    rows: list[Row] = []
    for sleeping in (True, False):
        r = imp[(n, sleeping)]
        tag = "" if sleeping else ", no sleep"
        who = "impulse2d sleeping on" if sleeping else "impulse2d sleeping=False"
        who += f", {r['threads']} threads" if n > 1 else ", a World.step call a step"
        partial = "; " + _steps_note(plan, r)
        if n > 1 and plan.pool_steps != r["steps"]:  # pymunk's batch runs have no budget
            partial += f"; pymunk {plan.pool_steps} steps"
        ws_i, ws_p = r["world_steps_per_s"], pm["world_steps_per_s"]
        us_note = "lower is better"
        if n == 1 and sleeping:
            us_note += "; " + _single_target(ws_p / ws_i)
        rows.append(
            (
                f"pool break{tag}: world-steps/s",
                str(n),
                fmt(ws_i),
                fmt(ws_p),
                ratio(ws_i, ws_p),
                who + partial,
            )
        )
        rows.append(
            (
                f"pool break{tag}: us/world-step",
                str(n),
                fmt(1e6 / ws_i),
                fmt(1e6 / ws_p),
                ratio(1e6 / ws_i, 1e6 / ws_p),
                us_note,
            )
        )
        if n == 1:
            us = r["step_us"]
            rows.append(
                (
                    f"pool break{tag}: mean us/step",
                    "1",
                    fmt(float(us.mean())),
                    "-",
                    "-",
                    f"per World.step call, Python included; median {np.median(us):.1f}, max "
                    f"{us.max():.0f} us (step {int(us.argmax()) + 1})",
                )
            )
    return rows


def pool_single_world(plan: Plan, imp: Runs, rows: list[Row]) -> dict:
    """Time the pool break in one world: impulse2d sleeping on and off (median run, and
    whether the repeats ended identically) and pymunk. Returns pymunk's median run."""
    single_repeats = plan.single_repeats
    for sleeping in (True, False):
        _stage(f"impulse2d pool break, 1 world, sleeping={sleeping}")
        runs = [
            pool_break_impulse2d(1, plan.pool_steps, POOL_SUBSTEPS, sleeping)
            for _ in range(single_repeats)
        ]
        deterministic = all(
            np.array_equal(r["final_positions"], runs[0]["final_positions"]) for r in runs
        )
        res = sorted(runs, key=lambda r: r["seconds"])[single_repeats // 2]
        res["deterministic"] = deterministic
        imp[(1, sleeping)] = res
    _stage("pymunk pool break, 1 world")
    pm_runs = [
        pymunk_peer.pool_break_pymunk(1, plan.pool_steps) for _ in range(PYMUNK_SINGLE_REPEATS)
    ]
    pm1 = sorted(pm_runs, key=lambda r: r["seconds"])[PYMUNK_SINGLE_REPEATS // 2]
    rows += _pool_rows(plan, imp, 1, pm1)
    return pm1


def pool_one_call(plan: Plan, imp: Runs, pm1: dict, rows: list[Row]) -> None:
    """The single-world break as one compiled call, ``World.step(dt, steps=...)``, sleeping
    on, against pymunk's single-world run ``pm1`` and the Python loop of calls."""
    _stage(f"impulse2d pool break, 1 world, one World.step(dt, steps={plan.pool_steps}) call")
    one = pool_break_one_call(plan.pool_steps, POOL_SUBSTEPS, True, repeats=plan.single_repeats)
    loop = imp[(1, True)]
    us_i, us_p = 1e6 / one["world_steps_per_s"], 1e6 / pm1["world_steps_per_s"]
    same = bool(np.array_equal(one["final_positions"], loop["final_positions"]))
    rows.append(
        (
            "pool break, one call for all steps: us/world-step",
            "1",
            fmt(us_i),
            fmt(us_p),
            ratio(us_i, us_p),
            f"World.step(dt, steps={plan.pool_steps}), sleeping on; {_single_target(us_i / us_p)}"
            f"; x{(1e6 / loop['world_steps_per_s']) / us_i:.2f} faster than a call a step; "
            f"final state == the call-a-step run: {same}; repeats identical: "
            f"{one['repeats_identical']}",
        )
    )


def pool_batch(plan: Plan, imp: Runs, rows: list[Row]) -> dict:
    """Time the pool break in ``plan.n_worlds`` worlds: impulse2d sleeping on alternating with
    pymunk, then impulse2d sleeping off. Returns pymunk's median run."""
    n_worlds, pool_steps, budget = plan.n_worlds, plan.pool_steps, plan.budget
    _stage(f"impulse2d and pymunk pool break, {n_worlds} worlds, alternating")
    imp[(n_worlds, True)], pmN = _paired_runs(
        lambda: pool_break_impulse2d(n_worlds, pool_steps, POOL_SUBSTEPS, True, budget_s=budget),
        lambda: pymunk_peer.pool_break_pymunk(n_worlds, pool_steps),
        plan.batch_repeats,
    )
    _stage(f"impulse2d pool break, {n_worlds} worlds, sleeping=False")
    imp[(n_worlds, False)] = _median_run(
        lambda: pool_break_impulse2d(n_worlds, pool_steps, POOL_SUBSTEPS, False, budget_s=budget),
        plan.batch_repeats,
    )
    rows += _pool_rows(plan, imp, n_worlds, pmN)
    return pmN


def pool_one_substep(plan: Plan, pmN: dict, rows: list[Row]) -> None:
    """The same batch with one substep: cheaper, at the cost of deeper overlaps in the rack."""
    n_worlds, pool_steps = plan.n_worlds, plan.pool_steps
    _stage(f"impulse2d pool break, {n_worlds} worlds, substeps=1")
    one = _median_run(
        lambda: pool_break_impulse2d(n_worlds, pool_steps, 1, True, budget_s=plan.budget),
        plan.batch_repeats,
    )
    one_check = pool_check_impulse2d(pool_steps, 1, True)
    rows.append(
        (
            "pool break, substeps=1: world-steps/s",
            str(n_worlds),
            fmt(one["world_steps_per_s"]),
            fmt(pmN["world_steps_per_s"]),
            ratio(one["world_steps_per_s"], pmN["world_steps_per_s"]),
            f"impulse2d sleeping on, {one['threads']} threads, 1 substep (h = 1/120 s); "
            f"deepest ball overlap {one_check['max_overlap_m'] * 1e3:.1f} mm (2 substeps: see "
            "below); pymunk as above",
        )
    )


def pool_batch_matches_single(plan: Plan, imp: Runs, rows: list[Row]) -> None:
    """World 0 of each batch run against the single world, bitwise (replayed untimed over
    the same steps when the batch stopped early)."""
    n_worlds = plan.n_worlds
    for sleeping in (True, False):
        r = imp[(n_worlds, sleeping)]
        if r["steps"] == plan.pool_steps:
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


def pool_checks(plan: Plan, imp: Runs, pm1: dict, rows: list[Row]) -> None:
    """Replay the single-world break untimed (:func:`pool_check_impulse2d`): momentum, energy,
    balls on the table and overlaps, against pymunk's single-world run ``pm1``."""
    scene, pool_steps = plan.scene, plan.pool_steps
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
            fmt(1e3 * chk["max_overlap_m"]),
            "-",
            "-",
            f"deepest ball-ball overlap after any step; deepest past a cushion face "
            f"{1e3 * chk['max_penetration_m']:.3g} mm",
        )
    )


def pool_varied_shots(plan: Plan, imp: Runs, rows: list[Row]) -> None:
    """The batch with one shot per world (the realistic RL case), both engines alternating,
    against the target; then worlds of the batch against single worlds, bitwise."""
    n_worlds, pool_steps = plan.n_worlds, plan.pool_steps
    offsets = pool_cue_offsets(n_worlds)
    _stage(f"impulse2d and pymunk pool break, varied shots, {n_worlds} worlds, alternating")
    var, pmV = _paired_runs(
        lambda: pool_break_impulse2d(
            n_worlds, pool_steps, POOL_SUBSTEPS, True, budget_s=plan.budget, cue_y_offsets=offsets
        ),
        lambda: pymunk_peer.pool_break_pymunk(n_worlds, pool_steps, offsets),
        plan.batch_repeats,
    )
    ws_i, ws_p = var["world_steps_per_s"], pmV["world_steps_per_s"]
    same_shot = imp[(n_worlds, True)]
    vs_same = (
        f"; x{ws_i / same_shot['world_steps_per_s']:.2f} the identical-shot impulse2d rate"
        if same_shot["steps"] == var["steps"]
        else ""
    )
    met = _ok(ws_i / ws_p >= VARIED_RATIO_TARGET)
    rows.append(
        (
            "pool break, varied shots: world-steps/s",
            str(n_worlds),
            fmt(ws_i),
            fmt(ws_p),
            ratio(ws_i, ws_p),
            f"target ratio >= {VARIED_RATIO_TARGET:g} (impulse2d {var['threads']} threads, "
            f"pymunk 1 process): {met}; impulse2d sleeping on (its default), pymunk sleeping "
            f"off as elsewhere; {_steps_note(plan, var)}{vs_same}",
        )
    )
    rows.append(
        (
            "pool break, varied shots: us/world-step",
            str(n_worlds),
            fmt(1e6 / ws_i),
            fmt(1e6 / ws_p),
            ratio(1e6 / ws_i, 1e6 / ws_p),
            "lower is better",
        )
    )
    rows.append(_varied_matches_single(plan, var, pmV, offsets))


def _varied_matches_single(plan: Plan, var: dict, pmV: dict, offsets: np.ndarray) -> Row:
    """World i of the varied batch (cue moved with the batch setter) against a single world
    built directly from ``pool_break(offsets[i])``: the setter must give the same start."""
    n_worlds = plan.n_worlds
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
    return (
        "pool break, varied shots: world i == 1 world",
        str(n_worlds),
        str(all(d == 0.0 for d in diffs)),
        "-",
        "-",
        f"bitwise, worlds {checked} against single worlds built at their offsets (max |diff| "
        f"{max(diffs):.3g} m); {distinct} of {n_worlds} final states distinct; finite: "
        f"{var['finite']}; pymunk world 0 momentum err {pmV['momentum_error']:.1e}",
    )


# -- Box2D v3 columns -------------------------------------------------------------------------
NOT_INSTALLED = "not installed"


def _median_ms(run: Callable[[], dict], repeats: int) -> dict:
    """Run a benchmark ``repeats`` times and keep the run of median ms/step."""
    runs = sorted((run() for _ in range(repeats)), key=lambda r: r["ms_per_step"])
    return runs[len(runs) // 2]


def _box2d_run(run: Callable[[], dict], repeats: int) -> dict | None:
    """:func:`_median_ms` of a Box2D benchmark, or None when pyb2d3 is not installed."""
    return _median_ms(run, repeats) if box2d_peer.AVAILABLE else None


def box2d_cells(
    imp: float, b2: float | None, cell: Callable[[float], str] = fmt
) -> tuple[str, str]:
    """The Box2D v3 value and the ratio impulse2d / Box2D, or "not installed" and "-"."""
    if b2 is None:
        return NOT_INSTALLED, "-"
    return cell(b2), ratio(imp, b2)


def _drift(value: float) -> str:
    """A distance cell (m), to 0.1 mm as the pyramid rows have always been printed."""
    return f"{value:.4f}"


def _who(b2: dict | None) -> str:
    """Which engines a note's "a / b / c" lists, in order."""
    return "impulse2d / pymunk" + (" / Box2D" if b2 else "")


# -- pyramids --------------------------------------------------------------------------------
def pyramids(plan: Plan, rows: list[Row]) -> None:
    """Box pyramids of base 10 and 20: time per step and drift, every engine; the targets
    (against pymunk) are for base 20."""
    pyr_steps, drift_steps = plan.pyr_steps, plan.drift_steps
    for base in (10, 20):
        _stage(f"pyramid base {base}")
        ri = pyramid_impulse2d(base, pyr_steps, drift_steps, repeats=PYRAMID_REPEATS)
        rp = _median_ms(
            partial(pymunk_peer.pyramid_pymunk, base, pyr_steps, drift_steps), PYRAMID_REPEATS
        )
        rb = _box2d_run(
            partial(box2d_peer.pyramid_box2d, base, pyr_steps, drift_steps), PYRAMID_REPEATS
        )
        speed_note = drift_note = ""
        if base == PYRAMID_TARGET_BASE:
            fast = ri["ms_per_step"] / rp["ms_per_step"] <= PYRAMID_RATIO_TARGET
            speed_note = f"target ratio <= {PYRAMID_RATIO_TARGET:g}: {_ok(fast)}; "
            drift_note = f"target <= pymunk: {_ok(ri['top_drift_m'] <= rp['top_drift_m'])}; "
        b2_max = f" / {rb['max_drift_m']:.4f}" if rb else ""
        rows.append(
            (
                f"pyramid base {base}: ms/step",
                "1",
                fmt(ri["ms_per_step"]),
                fmt(rp["ms_per_step"]),
                ratio(ri["ms_per_step"], rp["ms_per_step"]),
                *box2d_cells(ri["ms_per_step"], rb and rb["ms_per_step"]),
                f"{speed_note}first {pyr_steps} steps, a World.step call a step",
            )
        )
        rows.append(
            (
                f"pyramid base {base}: top drift (m)",
                "1",
                _drift(ri["top_drift_m"]),
                _drift(rp["top_drift_m"]),
                ratio(ri["top_drift_m"], rp["top_drift_m"]),
                *box2d_cells(ri["top_drift_m"], rb and rb["top_drift_m"], _drift),
                f"after {drift_steps * plan.dt_pyr:g} s; {drift_note}max drift "
                f"{ri['max_drift_m']:.4f} / {rp['max_drift_m']:.4f}{b2_max} m ({_who(rb)}); "
                f"finite: {ri['finite']}",
            )
        )


def large_pyramid(plan: Plan, rows: list[Row]) -> None:
    """Box2D v3's ``large_pyramid`` benchmark (5,050 boxes, ``plan.large_steps`` steps) in
    impulse2d and Box2D: ms/step, and how far the pyramid has settled after the last step
    (apex sink, largest sideways movement, boxes that crept). pymunk does not run it."""
    if not plan.large_steps:
        return
    steps = plan.large_steps
    _stage(f"large_pyramid, 5,050 boxes, {steps} steps (impulse2d, then Box2D)")
    ri = large_pyramid_impulse2d(steps, plan.large_budget)
    rb = _box2d_run(partial(box2d_peer.large_pyramid_box2d, steps), 1)
    timed = (
        f"first {ri['timed_steps']} of {steps} steps timed (budget {plan.large_budget:g} s)"
        if ri["timed_steps"] < steps
        else f"{steps} steps timed"
    )
    creep = "max |dx| {:.3f} m, {} boxes moved > {:g} m sideways"
    b2_creep = creep.format(rb["max_dx_m"], rb["crept"], LATERAL_CREEP_M) if rb else NOT_INSTALLED
    rows.append(
        (
            "large_pyramid (5,050 boxes): ms/step",
            "1",
            fmt(ri["ms_per_step"]),
            "-",
            "-",
            *box2d_cells(ri["ms_per_step"], rb and rb["ms_per_step"]),
            f"{timed}, from the first; impulse2d median step {ri['median_step_ms']:.3g} ms, "
            f"build {ri['build_s']:.1f} s (untimed)" + ("; Box2D one thread" if rb else ""),
        )
    )
    rows.append(
        (
            "large_pyramid: apex sink (m)",
            "1",
            _drift(ri["apex_sink_m"]),
            "-",
            "-",
            *box2d_cells(ri["apex_sink_m"], rb and rb["apex_sink_m"], _drift),
            f"after {steps} steps ({steps * plan.dt_pyr:.3g} s); impulse2d "
            f"{creep.format(ri['max_dx_m'], ri['crept'], LATERAL_CREEP_M)}; Box2D {b2_creep}; "
            f"finite: {ri['finite'] and (rb is None or rb['finite'])}",
        )
    )


# -- rain: cost against scene size -----------------------------------------------------------
def rains(plan: Plan, rows: list[Row]) -> None:
    """The rain at each of ``plan.rain_counts`` bodies: time per step, every engine, and how
    it grows from the previous count."""
    rain_scene, rain_repeats = plan.rain_scene, plan.rain_repeats
    steps, settle = rain_scene.steps, rain_scene.settle_steps
    previous: tuple[int, dict, dict] | None = None
    for count in plan.rain_counts:
        _stage(f"rain {count} bodies (impulse2d builds, settles and steps, then pymunk, Box2D)")
        ri = rain_impulse2d(count, steps, settle, repeats=rain_repeats)
        rp = _median_ms(partial(pymunk_peer.rain_pymunk, count, steps, settle), rain_repeats)
        rb = _box2d_run(partial(box2d_peer.rain_box2d, count, steps, settle), rain_repeats)
        growth = ""
        if count == RAIN_TARGET_COUNT:
            met = ri["ms_per_step"] / rp["ms_per_step"] <= RAIN_RATIO_TARGET
            growth = f"target ratio <= {RAIN_RATIO_TARGET:g}: {_ok(met)}; "
        if previous is not None:
            n0, ri0, rp0 = previous
            growth += (
                f"x{ri['ms_per_step'] / ri0['ms_per_step']:.2f} for {count / n0:g}x the bodies "
                f"(pymunk x{rp['ms_per_step'] / rp0['ms_per_step']:.2f}); "
            )
        b2_y = f" / {rb['mean_y']:.3f}" if rb else ""
        rows.append(
            (
                f"rain {count} bodies: ms/step",
                "1",
                fmt(ri["ms_per_step"]),
                fmt(rp["ms_per_step"]),
                ratio(ri["ms_per_step"], rp["ms_per_step"]),
                *box2d_cells(ri["ms_per_step"], rb and rb["ms_per_step"]),
                f"{growth}mean height {ri['mean_y']:.3f} / {rp['mean_y']:.3f}{b2_y} m "
                f"({_who(rb)}); finite: "
                f"{ri['finite'] and rp['finite'] and (rb is None or rb['finite'])}; repeats "
                f"identical: {ri['repeats_identical']}; impulse2d build {ri['build_s']:.1f} s "
                "(untimed)",
            )
        )
        previous = (count, ri, rp)


SETTLED_RAIN_STEPS = 600  # 10 s untimed: the piles come to rest and fall asleep


def settled_rain(plan: Plan, rows: list[Row]) -> None:
    """The largest rain with sleeping on in every engine (each with its defaults: asleep
    after 0.5 s nearly still), timed after ``SETTLED_RAIN_STEPS`` untimed steps, when
    nearly every body sleeps: what a world at rest costs, beside Box2D's solver sets and
    Chipmunk's sleeping components."""
    count, steps = plan.rain_counts[-1], plan.rain_scene.steps
    _stage(f"rain {count} bodies at rest, sleeping on (each engine settles 10 s untimed)")
    ri = settled_rain_impulse2d(count, steps, SETTLED_RAIN_STEPS)
    rp = pymunk_peer.settled_rain_pymunk(count, steps, SETTLED_RAIN_STEPS)
    rb = (
        box2d_peer.settled_rain_box2d(count, steps, SETTLED_RAIN_STEPS)
        if box2d_peer.AVAILABLE
        else None
    )
    awake = f"{ri['awake']} / {rp['awake']}" + (f" / {rb['awake']}" if rb else "")
    rows.append(
        (
            f"rain {count} at rest, sleeping on: ms/step",
            "1",
            fmt(ri["ms_per_step"]),
            fmt(rp["ms_per_step"]),
            ratio(ri["ms_per_step"], rp["ms_per_step"]),
            *box2d_cells(ri["ms_per_step"], rb and rb["ms_per_step"]),
            f"{steps} steps timed after {SETTLED_RAIN_STEPS} untimed; bodies awake at the end "
            f"{awake} ({_who(rb)}); finite: {ri['finite']}",
        )
    )
