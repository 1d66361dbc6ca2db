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


def test_padding_keeps_each_colour_and_adds_empty_lanes(scene):
    con, pair = scene.con[:, scene.order], scene.pair[scene.order]
    padded, padded_pair, starts = probe.pad_colours(con, pair, scene.starts, 4, scene.dummy)
    assert np.all(np.diff(starts) % 4 == 0)
    assert padded.shape[1] == starts[-1] and padded_pair.shape[0] == starts[-1]
    real = ~np.all(padded_pair == scene.dummy, axis=1)
    np.testing.assert_array_equal(padded[:, real], con)


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_blocks_of_four_solve_bitwise_as_lane_by_lane(scene, dtype):
    """Blocks change when the lanes are stored, not what they compute."""
    results = []
    for blocks in (False, True):
        args = scene.coloured_args(dtype, 3, blocks)
        layout.coloured(*args)
        states, con, pair = args[0], args[1], args[2]
        real = ~np.all(pair == scene.dummy, axis=1)
        results.append((states.copy(), con[:, real].copy()))
    np.testing.assert_array_equal(results[0][0], results[1][0])
    np.testing.assert_array_equal(results[0][1], results[1][1])
    assert results[0][0].dtype == dtype


def test_every_order_converges_to_the_same_impulses(scene):
    """Gauss-Seidel in the narrowphase's order and in colour order solve one convex
    problem (soft contacts): the gap between them shrinks as passes are added, and the
    ground carries the pyramid's weight over the substep."""
    gaps = []
    for passes in (25, 400):
        compact_con = scene.con.copy()
        states = probe.body_states(scene.cap, np.float64)
        layout.compact(states, compact_con, scene.pair, scene.consts(np.float64), passes)
        args = scene.coloured_args(np.float64, passes, False)
        layout.coloured(*args)
        normal = layout.POINT0 + layout.PNJ
        gap = np.abs(compact_con[normal][scene.order] - args[1][normal]).max()
        gaps.append(gap / np.abs(compact_con[normal]).max())
        share = layout.ground_share(args[1], args[2], scene.dummy, scene.weight_impulse)
        assert 0.9 < share < 1.2
    assert gaps[1] < gaps[0] / 4


def test_the_probe_prints_its_table(capsys, monkeypatch):
    monkeypatch.setattr(sys, "argv", ["solver_probe.py", "--quick"])
    probe.main()
    out = capsys.readouterr().out
    assert "today: core.solver.sweep" in out and "floor: normals only" in out
    assert out.count("float32") == 4 and "packed ymm/zmm" in out
