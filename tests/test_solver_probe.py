"""The solver-layout probe (``bench/solver_probe.py``): its compact layout holds the step's
contacts, its colouring is a colouring, and its kernels solve the same constraints.

The probe's figures steer the solver's redesign, so what it times must be the same
problem in every layout: these tests check that on the captured pyramid step.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "bench"))
import solver_probe as probe
import solver_probe_kernels as layout


@pytest.fixture(scope="module")
def scene():
    return probe.Scene()


def test_manifolds_hold_every_point_once(scene):
    """Every narrowphase point lands in one manifold slot, with its impulses; empty
    second slots have zero masses."""
    points, n = scene.cap["points"], scene.n
    con, second = scene.con, layout.POINT0 + layout.PER_POINT
    normal_masses = np.concatenate([con[layout.POINT0 + layout.PNM], con[second + layout.PNM]])
    assert np.count_nonzero(normal_masses) == n
    stored = np.concatenate([con[layout.POINT0 + layout.PNJ], con[second + layout.PNJ]])
    assert np.isclose(stored.sum(), points[:, probe.NORMAL_J].sum(), rtol=1e-12)
    assert n > 500  # the 20-row pyramid: about two points a touching pair


def test_colouring_shares_no_moving_body(scene):
    colours = probe.colour(scene.pair, scene.dummy)
    for c in range(colours.max() + 1):
        members = scene.pair[colours == c]
        moving = members[members != scene.dummy]
        assert moving.size == np.unique(moving).size, f"colour {c} repeats a body"
    # greedy: a manifold's colour is the first its bodies leave free
    assert colours.max() + 1 <= 8


def test_colour_and_sort_puts_each_colour_together(scene):
    colours = np.zeros(scene.pair.shape[0], np.int64)
    sorted_con, sorted_pair = np.empty_like(scene.con), np.empty_like(scene.pair)
    starts = np.zeros(65, np.int64)
    count = layout.colour_and_sort(scene.con, scene.pair, scene.dummy, colours, sorted_con,
                                   sorted_pair, starts)  # fmt: skip
    assert count == scene.starts.size - 1
    np.testing.assert_array_equal(starts[: count + 1], scene.starts)
    np.testing.assert_array_equal(sorted_pair, scene.pair[scene.order])  # a stable sort
    np.testing.assert_array_equal(sorted_con, scene.con[:, scene.order])


def test_padding_keeps_each_colour_and_adds_empty_lanes(scene):
    con, pair = scene.con[:, scene.order], scene.pair[scene.order]
    padded, padded_pair, starts = probe.pad_colours(con, pair, scene.starts, 4, scene.dummy)
    assert np.all(np.diff(starts) % 4 == 0)
    assert padded.shape[1] == starts[-1] and padded_pair.shape[0] == starts[-1]
    real = ~np.all(padded_pair == scene.dummy, axis=1)
    np.testing.assert_array_equal(padded[:, real], con)


@pytest.mark.parametrize("how", [layout.BLOCKS_OF_FOUR, layout.VECTOR])
@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_blocks_and_vectors_solve_bitwise_as_lane_by_lane(scene, dtype, how):
    """Blocks change when the lanes are stored, vectors how many are computed at once:
    neither changes what a lane computes."""
    results = []
    for solve in (layout.LANE_BY_LANE, how):
        args = scene.coloured_args(dtype, 3, solve)
        layout.coloured(*args)
        states, con, pair = args[0], args[1], args[2]
        real = ~np.all(pair == scene.dummy, axis=1)
        results.append((states.copy(), con[:, real].copy()))
    np.testing.assert_array_equal(results[0][0], results[1][0])
    np.testing.assert_array_equal(results[0][1], results[1][1])
    assert results[0][0].dtype == dtype


def test_the_block_solve_vectorised_is_bitwise_lane_by_lane(scene):
    results = []
    for vector in (False, True):
        args = (*scene.coloured_args(np.float64, 3, layout.LANE_BY_LANE)[:-1], vector)
        layout.coloured_block(*args)
        results.append((args[0].copy(), args[1].copy()))
    np.testing.assert_array_equal(results[0][0], results[1][0])
    np.testing.assert_array_equal(results[0][1], results[1][1])


def test_the_block_solve_by_selects_is_the_block_solve(scene):
    """The branch-free block solve gives the branchy one's bits (each manifold its own
    one-lane colour reproduces the narrowphase order), and solving a manifold's two normals
    together is not solving them one after the other."""
    consts = scene.consts(np.float64)
    outcomes = {}
    for name, kernel in (("block", layout.compact_block), ("sequential", layout.compact)):
        con, states = scene.con.copy(), probe.body_states(scene.cap, np.float64)
        kernel(states, con, scene.pair, consts, 3)
        outcomes[name] = (states, con)
    con, states = scene.con.copy(), probe.body_states(scene.cap, np.float64)
    lanes = np.zeros((layout.LANE_F, scene.pair.shape[0]))
    one_lane_colours = np.arange(scene.pair.shape[0] + 1)
    layout.coloured_block(states, con, scene.pair, one_lane_colours, lanes, consts, 3, False)
    np.testing.assert_array_equal(states, outcomes["block"][0])
    np.testing.assert_array_equal(con, outcomes["block"][1])
    assert not np.array_equal(outcomes["block"][1], outcomes["sequential"][1])


def test_every_order_converges_to_the_same_impulses(scene):
    """Gauss-Seidel in the narrowphase's order and in colour order solve one convex
    problem (soft contacts): the gap between them shrinks as passes are added, and the
    ground carries the pyramid's weight over the substep."""
    gaps = []
    for passes in (25, 400):
        compact_con = scene.con.copy()
        states = probe.body_states(scene.cap, np.float64)
        layout.compact(states, compact_con, scene.pair, scene.consts(np.float64), passes)
        args = scene.coloured_args(np.float64, passes, layout.LANE_BY_LANE)
        layout.coloured(*args)
        normal = layout.POINT0 + layout.PNJ
        gap = np.abs(compact_con[normal][scene.order] - args[1][normal]).max()
        gaps.append(gap / np.abs(compact_con[normal]).max())
        share = layout.ground_share(args[1], args[2], scene.dummy, scene.weight_impulse)
        assert 0.9 < share < 1.2
    assert gaps[1] < gaps[0] / 3


def test_the_pool_break_has_one_point_manifolds():
    pool = probe.Scene("pool")
    second = layout.POINT0 + layout.PER_POINT + layout.PNM
    assert pool.n == pool.pair.shape[0] and not pool.con[second].any()
    colours = probe.colour(pool.pair, pool.dummy)
    for c in range(colours.max() + 1):
        moving = pool.pair[colours == c]
        moving = moving[moving != pool.dummy]
        assert moving.size == np.unique(moving).size


def test_the_probe_prints_its_table(capsys, monkeypatch):
    monkeypatch.setattr(sys, "argv", ["solver_probe.py", "--quick"])
    probe.main()
    out = capsys.readouterr().out
    assert "colouring them and sorting into colour order" in out
    assert "plain order: core.solver.sweep" in out and "floor: normals only" in out
    assert "engine, coloured: core.solver.sweep with core.lanes" in out
    assert out.count("float32") == 5 and "packed ymm/zmm" in out
    assert "block solve by selects, lane loop vectorised" in out


def _has_avx2() -> bool:
    import llvmlite.binding

    return llvmlite.binding.get_host_cpu_features().get("avx2", False)


@pytest.mark.skipif(not _has_avx2(), reason="counts AVX2/AVX-512 instructions")
def test_the_vector_lane_loop_is_vectorised():
    """The probe's claim that the lane loop vectorises, checked in the machine code numba
    compiled for this CPU; the scalar lane loop has no vectorised loop."""
    consts = np.array([240.0, 3.0, 0.0, 1.0])
    for solve in (layout.solve_vector, layout.solve_lanes):
        solve(np.zeros((layout.CON_F, 8)), np.zeros((layout.LANE_F, 8)), 0, 8, consts)
    scalar = probe.packed_instructions(layout.solve_lanes)
    assert probe.packed_instructions(layout.solve_vector) > 10 * max(scalar, 1)


def test_the_substep_stages_bench_prints_every_stage(capsys, monkeypatch):
    """``bench/substep_stages.py`` times each substep stage plain and coloured on the
    captured pyramid step: every world point coloured, every row a positive time."""
    import substep_stages

    monkeypatch.setattr(sys, "argv", ["substep_stages.py", "--quick"])
    substep_stages.main()
    out = capsys.readouterr().out
    assert "pyramid: 800 points, 400 manifolds coloured" in out
    for stage in ("solve pass, coloured", "anchors follow, coloured", "packing (once a step)"):
        assert stage in out


def test_the_threshold_bench_prints_both_orders_and_restores_the_threshold(capsys, monkeypatch):
    import colouring_threshold
    from impulse2d.core import colouring

    before = colouring.COLOUR_FROM_POINTS
    monkeypatch.setattr(sys, "argv", ["colouring_threshold.py", "--quick"])
    colouring_threshold.main()
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].split() == ["rows", "points", "plain", "us", "coloured", "us", "ratio"]
    assert [line.split()[:2] for line in lines[1:]] == [["3", "18"], ["6", "72"]]
    assert colouring.COLOUR_FROM_POINTS == before
