"""The coloured solver stage by stage (``core.colouring``: which manifolds, which colours,
colour order; ``core.lanes``: one manifold's solve, the vectorised lane loop), and whole
worlds coloured against plain order: the same physics, bitwise the same alone, in a
batch and on any number of threads."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import impulse2d as p2
from impulse2d.core import colouring, contacts, context, integrate, lanes, solver
from impulse2d.core.contacts import set_jacobian
from impulse2d.core.state import ANGLE, BODY_F, OMEGA, VX, VY, X, Y
from impulse2d.core.workspace import (
    AGAINST_PLANE,
    BIAS_RATE,
    CFRICTION,
    CIIA,
    CIIB,
    CIMA,
    CIMB,
    COLOURS,
    CON_F,
    GROSS_J,
    IIA,
    IIB,
    IMA,
    IMB,
    IMPULSE_SCALE,
    IN_COLOUR,
    LANE_F,
    MASS_SCALE,
    MAX_J,
    MIXED_FRICTION,
    MOVABLE,
    MOVING,
    NORMAL_J,
    NORMAL_MASS,
    NX,
    NY,
    PNORMAL_J,
    PNORMAL_MASS,
    POINT_F,
    PSEP0,
    PTANGENT_MASS,
    RAX,
    RAY,
    RBX,
    RBY,
    RNA,
    RNB,
    RTA,
    RTB,
    SEP0,
    SHARED,
    STATE_F,
    STEP_J,
    TANGENT_J,
    TANGENT_MASS,
    TERMS,
    colour_scratch,
    manifold_room,
)


def _points(pairs, bodies, movable=None):
    """Points and ids for ``pairs``, a list of ``(a, b, points, normal, against_plane)``;
    terms with ``MOVABLE`` from ``movable`` (all movable by default)."""
    n = sum(p[2] for p in pairs)
    points, ids = np.zeros((n, POINT_F)), np.zeros((n, 3), np.int64)
    k = 0
    for a, b, count, normal, plane in pairs:
        for feature in range(count):
            points[k, NX], points[k, NY] = normal
            points[k, AGAINST_PLANE] = 1.0 if plane else 0.0
            ids[k] = a, b, feature
            k += 1
    terms = np.zeros((bodies, TERMS))
    terms[:, MOVABLE] = 1.0 if movable is None else np.asarray(movable, float)
    return points, ids, terms


def _colour(points, ids, terms):
    n, m = len(points), manifold_room(len(points))
    masks = np.zeros(len(terms), np.int64)
    found, colours, order = (np.zeros(m, np.int64) for _ in range(3))
    starts, others = np.zeros(COLOURS + 1, np.int64), np.full(2 * m, -1)
    count = colouring.colour_manifolds(terms, points, ids, n, masks, found, colours, order, starts,
                                       others)  # fmt: skip
    of = {int(order[i]): c for c in range(COLOURS) for i in range(starts[c], starts[c + 1])}
    _assert_others(points, ids, n, others)
    return count, order[:count], starts, of


def _assert_others(points, ids, n, others):
    """``others`` lists the first point of every manifold not coloured, in narrowphase
    order, then ``n``: what the plain passes walk (``colouring.pair_at``)."""
    firsts = [k for k in range(n) if k == 0 or tuple(ids[k, :2]) != tuple(ids[k - 1, :2])]
    expected = [k for k in firsts if points[k, AGAINST_PLANE] != IN_COLOUR] + [n]
    assert others[: len(expected)].tolist() == expected


UP = (0.0, 1.0)


def _assert_valid(ids, terms, order, starts):
    """No two manifolds of a colour share a moving body; colours keep narrowphase order."""
    for c in range(COLOURS):
        members = order[starts[c] : starts[c + 1]]
        assert list(members) == sorted(members)
        moving = [int(i) for k in members for i in ids[k, :2] if terms[i, MOVABLE] != 0.0]
        assert len(moving) == len(set(moving)), c


def test_a_stack_alternates_colours_and_its_ground_takes_the_top_colour():
    # body 0 fixed (the ground), 1..6 a stack: 0-1, 1-2, ..., 5-6, two points each
    pairs = [(i, i + 1, 2, UP, False) for i in range(6)]
    points, ids, terms = _points(pairs, 7, movable=[0, 1, 1, 1, 1, 1, 1])
    count, order, starts, of = _colour(points, ids, terms)
    assert count == 6 and starts[COLOURS] == 6
    assert [of[2 * i] for i in range(6)] == [COLOURS - 1, 0, 1, 0, 1, 0]
    assert (points[:, AGAINST_PLANE] == IN_COLOUR).all()
    _assert_valid(ids, terms, order, starts)


def test_a_colour_step_lists_each_manifolds_bodies_in_colour_order():
    """``pair_bodies``: the passes read a manifold's bodies from ``body_a``, ``body_b``
    at its place in colour order, which must be its first point's ids."""
    pairs = [(i, i + 1, 2, UP, False) for i in range(6)] + [(0, 7, 2, UP, False)]
    points, ids, terms = _points(pairs, 8, movable=[0, 1, 1, 1, 1, 1, 1, 1])
    floats, ints = colour_scratch(len(terms), len(points))
    count = colouring.colour_step(terms, points, ids, len(points), floats, ints, 1.0)
    c = colouring.colour_arrays(floats, ints)
    assert count == 7
    np.testing.assert_array_equal(c.body_a[:count], ids[c.order[:count], 0])
    np.testing.assert_array_equal(c.body_b[:count], ids[c.order[:count], 1])
    listed = zip(c.body_a[:count].tolist(), c.body_b[:count].tolist(), strict=True)
    assert sorted(listed) == sorted((a, b) for a, b, *_ in pairs)


@pytest.mark.parametrize("points", [2, 64, 1000, 1 << 12, 1 << 17])
def test_constraint_rows_hold_every_manifold_and_are_an_odd_number_of_cache_lines(points):
    """A row of ``con`` and ``lanes`` holds every manifold the points can make, and is an
    odd number of 64-byte lines long, so the ~46 rows a lane reads at one index fall in
    different cache sets (``manifold_room``)."""
    room = manifold_room(points)
    assert room >= points // 2 + 1
    assert room % 8 == 0 and (room // 8) % 2 == 1
    assert room - (points // 2 + 1) < 16  # at most two lines over
    floats, _ = colour_scratch(4, points)
    assert floats.strides[0] % 128 == 64


def test_only_two_point_manifolds_between_bodies_with_one_normal_are_coloured():
    pairs = [
        (0, 1, 1, UP, False),  # one point (a disc)
        (1, 2, 3, UP, False),  # three points
        (2, 3, 2, UP, True),  # against a plane
        (3, 4, 2, UP, False),  # coloured
        (5, 6, 2, UP, False),  # neither body moves
    ]
    points, ids, terms = _points(pairs, 7, movable=[1, 1, 1, 1, 1, 0, 0])
    points[1 + 3 + 2 + 1, NX] = 1e-9  # ... and give (3, 4) a second normal: not coloured
    count, _, _, _ = _colour(points, ids, terms)
    assert count == 0 and not (points[:, AGAINST_PLANE] == IN_COLOUR).any()
    points[1 + 3 + 2 + 1, NX] = 0.0
    count, order, _, _ = _colour(points, ids, terms)
    assert count == 1 and list(order) == [6]  # others: [0, 1, 4, 8, 10] (_assert_others)
    assert points[:, AGAINST_PLANE].tolist() == [0.0] * 4 + [1.0, 1.0, IN_COLOUR, IN_COLOUR, 0, 0]


def test_what_finds_no_colour_stays_in_plain_order():
    # body 0 touches 30 moving bodies (a hub): 24 dynamic colours, 6 left over
    hub = [(0, i, 2, UP, False) for i in range(1, 31)]
    points, ids, terms = _points(hub, 31)
    count, order, starts, of = _colour(points, ids, terms)
    assert count == colouring.DYNAMIC_COLOURS
    assert sorted(of.values()) == list(range(colouring.DYNAMIC_COLOURS))
    coloured = points[:, AGAINST_PLANE] == IN_COLOUR
    assert coloured[: 2 * count].all() and not coloured[2 * count :].any()
    # against 40 fixed bodies: colours from the top down to 1, never 0, 9 left over
    hub = [(0, i, 2, UP, False) for i in range(1, 41)]
    points, ids, terms = _points(hub, 41, movable=[1] + [0] * 40)
    count, order, starts, of = _colour(points, ids, terms)
    assert count == COLOURS - 1 and sorted(of.values()) == list(range(1, COLOURS))
    _assert_valid(ids, terms, order, starts)


@st.composite
def mixed_worlds(draw):
    """A world's pairs of every kind (discs, boxes, three points, against planes, fixed
    bodies), in random order, with random prepared columns."""
    kinds = st.tuples(st.integers(1, 3), st.booleans(), st.booleans())
    drawn = draw(st.lists(kinds, min_size=1, max_size=30))
    bodies = len(drawn) + 2
    pairs = [(i % bodies, (i + 1) % bodies, count, UP, plane)
             for i, (count, plane, _) in enumerate(drawn)]  # fmt: skip
    movable = [1.0] + [0.0 if fixed else 1.0 for *_, fixed in drawn] + [1.0]
    points, ids, terms = _points(pairs, bodies, movable)
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    for column in (SEP0, RNA, RNB, RTA, RTB, NORMAL_J, TANGENT_J):
        points[:, column] = rng.uniform(-0.1, 0.1, len(points))
    for column in (IMA, IMB, IIA, IIB, NORMAL_MASS, TANGENT_MASS, MIXED_FRICTION):
        points[:, column] = rng.uniform(0.1, 1.0, len(points))
    points[:, MASS_SCALE], points[:, IMPULSE_SCALE], points[:, BIAS_RATE] = 0.9, 0.1, 30.0
    body = np.zeros((1, bodies, BODY_F))
    body[0, :, [VX, VY, OMEGA]] = rng.uniform(-1.0, 1.0, (3, bodies))
    return body, terms, points, ids


@settings(max_examples=60, deadline=None)
@given(mixed_worlds(), st.booleans())
def test_the_plain_passes_of_a_coloured_world_walk_exactly_its_other_pairs(world, biased):
    """In a coloured world the plain passes walk the pairs ``others`` lists
    (``colouring.pair_at``): the sweep must match the sweep over every pair (which skips
    the coloured ones itself), bitwise; and warm starting and moving the anchors must
    leave the coloured points alone (here given no impulse and an immovable body, so
    the full walk leaves them alone too)."""
    body, terms, points, ids = world
    n = len(points)
    floats, ints = colour_scratch(len(terms), n)
    count = colouring.colour_step(terms, points, ids, n, floats, ints, 1.0)
    others = colouring.colour_arrays(floats, ints).others
    ctx = np.zeros(context.CONTEXT_SIZE)
    ctx[context.INV_H], ctx[context.PUSH_SPEED], ctx[context.COLOUR_FROM] = 240.0, 3.0, 1.0
    everything = np.zeros(0, np.int64)
    listed_body, listed_points = body.copy(), points.copy()
    solver.sweep(body, 0, ctx, terms, points, ids, n, biased, False, n - 2 * count, everything)
    solver.sweep(listed_body, 0, ctx, terms, listed_points, ids, n, biased, False,
                 n - 2 * count, others)  # fmt: skip
    assert body.tobytes() == listed_body.tobytes()
    assert points.tobytes() == listed_points.tobytes()
    coloured = points[:, AGAINST_PLANE] == IN_COLOUR
    points[coloured, NORMAL_J] = points[coloured, TANGENT_J] = points[coloured, IMA] = 0.0
    listed_points = points.copy()
    solver.warm_start(body, 0, points, ids, n, everything)
    solver.warm_start(listed_body, 0, listed_points, ids, n, others)
    contacts.follow_bodies(body, 0, ctx, terms, points, ids, n, everything)
    contacts.follow_bodies(listed_body, 0, ctx, terms, listed_points, ids, n, others)
    assert body.tobytes() == listed_body.tobytes()
    assert points.tobytes() == listed_points.tobytes()


@st.composite
def manifolds(draw):
    """One box-on-box manifold: bodies' states, the two points prepared as
    ``contacts.prepare`` and ``follow_bodies`` leave them."""
    f = st.floats(-1.0, 1.0)
    body = np.zeros((1, 2, BODY_F))
    for i in range(2):
        body[0, i, [VX, VY, OMEGA]] = draw(f) * 3, draw(f) * 3, draw(f) * 5
        body[0, i, [X, Y, ANGLE]] = draw(f) * 0.01, draw(f) * 0.01, draw(f) * 0.01
    terms = np.zeros((2, TERMS))
    terms[:, MOVING] = terms[:, MOVABLE] = 1.0  # both move, as awake dynamic bodies do
    points, ids = np.zeros((2, POINT_F)), np.array([[0, 1, 0], [0, 1, 1]])
    angle = draw(st.floats(-0.3, 0.3))
    nx, ny = np.sin(angle), np.cos(angle)
    inv_mass = draw(st.floats(0.1, 10.0)), draw(st.floats(0.1, 10.0))
    friction = draw(st.sampled_from([0.0, 0.3, 1.0]))
    soft = context.soft_constraint(30.0, 10.0, 1 / 240)
    for k, side in enumerate((-1.0, 1.0)):
        points[k, NX], points[k, NY] = nx, ny
        points[k, RAX], points[k, RAY] = side * 0.5 + draw(f) * 0.1, 0.5
        points[k, RBX], points[k, RBY] = points[k, RAX] - draw(f) * 0.05, -0.5
        points[k, SEP0] = draw(st.floats(-0.02, 0.01))
        points[k, IMA], points[k, IMB] = inv_mass
        points[k, IIA], points[k, IIB] = 6 * inv_mass[0], 6 * inv_mass[1]
        points[k, MIXED_FRICTION] = friction
        points[k, BIAS_RATE], points[k, MASS_SCALE], points[k, IMPULSE_SCALE] = soft
        points[k, NORMAL_J] = draw(st.floats(0.0, 2.0))
        points[k, TANGENT_J] = draw(st.floats(-0.5, 0.5)) * friction * points[k, NORMAL_J]
        points[k, SHARED] = 1.0
        set_jacobian(points, k, 0.0, 0.0, 0.0, 0.0)
    ctx = np.zeros(context.CONTEXT_SIZE)
    ctx[context.INV_H], ctx[context.PUSH_SPEED] = 240.0, 3.0
    return body, terms, points, ids, ctx, draw(st.booleans())


def _coloured(points, ids, terms):
    """The world's manifolds coloured and packed, as ``pipeline.colour`` does: the
    scratch and how many were coloured."""
    floats, ints = colour_scratch(len(terms), len(points))
    count = colouring.colour_step(terms, points, ids, len(points), floats, ints, 1.0)
    return floats, ints, count


@settings(max_examples=60, deadline=None)
@given(manifolds())
def test_a_lane_solves_a_manifold_as_the_plain_sweep_does(case):
    """One manifold, so colour order is narrowphase order: the lane's arithmetic (selects,
    deltas) must give the plain sweep's impulses and velocities, to rounding."""
    body, terms, points, ids, ctx, biased = case
    plain_body, plain_points = body.copy(), points.copy()
    solver.sweep(plain_body, 0, ctx, terms, plain_points, ids, 2, biased, False, 2,
                 np.zeros(0, np.int64))  # fmt: skip
    floats, ints, count = _coloured(points, ids, terms)
    assert count == 1 and (points[:, AGAINST_PLANE] == IN_COLOUR).all()
    values = (ctx[context.INV_H], ctx[context.PUSH_SPEED], biased)
    states = np.zeros((terms.shape[0], STATE_F))
    moving = np.zeros(terms.shape[0], np.int64)
    lanes.load_states(body, 0, terms, states)
    lanes.solve_coloured(states, values, floats, ints)
    lanes.store_states(body, 0, states, moving, integrate.list_moving(terms, moving))
    others = colouring.colour_arrays(floats, ints).others
    solver.sweep(body, 0, ctx, terms, points, ids, 2, biased, False, 0, others)  # nothing left
    colouring.unpack_step(points, floats, ints, count)
    for column in (NORMAL_J, TANGENT_J, STEP_J, MAX_J, GROSS_J):
        np.testing.assert_allclose(points[:, column], plain_points[:, column], rtol=1e-9,
                                   atol=1e-12, err_msg=str(column))  # fmt: skip
    np.testing.assert_allclose(body, plain_body, rtol=1e-9, atol=1e-12)
    assert (points[:, NORMAL_J] >= 0.0).all()
    assert (
        np.abs(points[:, TANGENT_J]) <= points[:, MIXED_FRICTION] * points[:, NORMAL_J] + 1e-15
    ).all()


def _random_lanes(seed, m):
    """Lanes and constraints of ``m`` made-up manifolds (every case of the block solve
    among them: pushing, parting, gaps, zero friction)."""
    rng = np.random.default_rng(seed)
    con, lane_rows = rng.normal(size=(CON_F, m)), rng.normal(size=(LANE_F, m))
    con[CFRICTION] = rng.choice([0.0, 0.5], m)
    for p in range(2):
        base = colouring.point_base(p)
        for f in (PNORMAL_J, PNORMAL_MASS, PTANGENT_MASS):
            con[base + f] = np.abs(con[base + f])
        con[base + PSEP0] *= 0.01
    for f in (CIMA, CIMB, CIIA, CIIB):
        con[f] = np.abs(con[f])
    return np.ascontiguousarray(con), np.ascontiguousarray(lane_rows)


@pytest.mark.parametrize("biased", [True, False])
def test_the_vectorised_lane_loop_is_bitwise_lane_by_lane_and_plain_python(biased):
    con, lane_rows = _random_lanes(1, 203)
    consts = (240.0, 3.0, biased)
    together = con.copy(), lane_rows.copy()
    lanes.solve_lanes(*together, 0, 203, consts)
    one_by_one = con.copy(), lane_rows.copy()
    for m in range(203):
        lanes.solve_lanes(*one_by_one, m, m + 1, consts)
    python = con.copy(), lane_rows.copy()
    lanes.solve_lanes.py_func(*python, 0, 203, consts)
    for other in (one_by_one, python):
        assert together[0].tobytes() == other[0].tobytes()
        assert together[1].tobytes() == other[1].tobytes()
    assert not np.array_equal(together[1], lane_rows)  # the lanes were solved


def _pyramid(base: int, threshold: float, monkeypatch) -> tuple[p2.World, float]:
    """Box2D's pyramid of ``base`` boxes on a fixed box, coloured from ``threshold``
    points; returns the world and its boxes' weight (N)."""
    monkeypatch.setattr(colouring, "COLOUR_FROM_POINTS", threshold)
    world = p2.World(substeps=4, sleeping=False)
    world.add(p2.Box(position=(0.0, -0.5), width=40.0, height=1.0, fixed=True, friction=0.6))
    for row in range(base):
        for j in range(base - row):
            x = (j - (base - row - 1) / 2) * 1.05
            world.add(p2.Box(position=(x, 0.5 + row), width=1.0, height=1.0, friction=0.6))
    return world, base * (base + 1) / 2 * 9.81


def _ground_load(world) -> float:
    """The normal impulse of the ground's contacts over the last step (N s)."""
    report = world.contacts()
    ground = (report.slot_a == 0) | (report.slot_b == 0)
    return float(report.impulse[ground].sum())


def test_a_coloured_pyramid_stands_as_the_plain_one(monkeypatch):
    """Same physics in either order: a 10-row pyramid (110 points) coloured holds still,
    bears its weight on the ground and ends where the plain one does, within 5 mm in 5 s
    (Gauss-Seidel in another order converges to nearly the same rest; each settles by
    1-2 cm as its soft contacts take the load)."""
    dt = 1 / 60
    ends = {}
    for name, threshold in (("plain", 1e9), ("coloured", 0.0)):
        world, weight = _pyramid(10, threshold, monkeypatch)
        start = world.state.body[0, 1:, :2].copy()
        for _ in range(300):
            world.step(dt)
        ends[name] = world.state.body[0, 1:, :2].copy()
        assert np.abs(ends[name] - start).max() < 0.02, name
        assert _ground_load(world) / dt == pytest.approx(weight, rel=0.02), name
    assert not np.array_equal(ends["plain"], ends["coloured"])  # another order was taken
    assert np.abs(ends["plain"] - ends["coloured"]).max() < 5e-3


def test_coloured_worlds_step_alike_alone_in_a_batch_and_on_two_threads(monkeypatch):
    dt = 1 / 60
    single, _ = _pyramid(6, 0.0, monkeypatch)
    start = single.snapshot()
    finals = []
    for threads in (1, 2):
        batch = single.replicate(3)
        batch.threads = threads
        batch.bodies[5].velocity = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, -3.0]])
        for _ in range(60):
            batch.step(dt)
        finals.append(batch.state.body.copy())
    assert finals[0].tobytes() == finals[1].tobytes()
    single.restore(start)
    for _ in range(60):
        single.step(dt)
    assert single.state.body[0].tobytes() == finals[0][0].tobytes()
    assert not np.array_equal(finals[0][1], finals[0][0])  # the worlds differ
