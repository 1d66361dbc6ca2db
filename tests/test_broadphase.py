"""The broadphase stage alone: its pairs are exactly the overlapping boxes that can touch,
in canonical order whatever the sweep's remembered order, and their number grows with the
scene's contacts, not with its size squared."""

import numpy as np
import pytest

import impulse2d as p2
from impulse2d.core import broadphase, integrate, workspace
from impulse2d.core.state import DYNAMIC, ENABLED, PLANE, SAP_ORDER
from impulse2d.core.workspace import BOTTOM, LEFT, MOVABLE, MOVING, RIGHT, TOP

DT = 1 / 60


def step_terms(world: p2.World, w: int = 0) -> np.ndarray:
    """``integrate.step_terms`` of world ``w`` as it stands: (B, TERMS)."""
    state = world.state
    terms = np.zeros((state.body.shape[1], workspace.TERMS))
    integrate.step_terms(
        state.body,
        state.body_i,
        world.layout.shapes,
        state.spring,
        world.layout.springs,
        state.hull,
        w,
        world.settings.step_context(DT),
        terms,
    )
    return terms


def candidate_pairs(world: p2.World, w: int = 0) -> np.ndarray:
    """The broadphase's pairs for world ``w`` as it stands: (P, 2) slots (A, B)."""
    ctx = world.settings.step_context(DT)
    state, shapes = world.state, world.layout.shapes
    n = state.body.shape[1]
    terms = step_terms(world, w)
    capacity = 16
    while True:
        pairs = np.zeros((capacity, 2), np.int64)
        scratch, buckets = np.zeros_like(pairs), np.zeros(n + 1, np.int64)
        swept = np.zeros((workspace.SWEPT_F, n))
        count = broadphase.find_pairs(
            state.body, state.body_i, shapes, w, ctx, terms, swept, pairs, scratch, buckets
        )
        if count <= capacity:
            return pairs[:count]
        capacity = count


def brute_force(world: p2.World, w: int = 0) -> set:
    """Every pair by the broadphase's rule, tested one by one."""
    state, shapes = world.state, world.layout.shapes
    n = state.body.shape[1]
    terms = step_terms(world, w)
    on = state.body_i[w, :, ENABLED] == 1
    kind, motion = shapes[:, 0], shapes[:, 1]
    found = set()
    for a in range(n):
        for b in range(a + 1, n):
            if not (on[a] and on[b]) or kind[a] < 0 or kind[b] < 0:
                continue
            if kind[a] == PLANE or kind[b] == PLANE:
                body_slot = b if kind[a] == PLANE else a
                if kind[a] != kind[b] and terms[body_slot, MOVABLE] == 1.0:
                    found.add((body_slot, a if body_slot == b else b))
                continue
            if terms[a, MOVING] == 0.0 and terms[b, MOVING] == 0.0:
                continue
            if motion[a] != DYNAMIC and motion[b] != DYNAMIC:
                continue
            near_x = terms[a, LEFT] < terms[b, RIGHT] and terms[b, LEFT] < terms[a, RIGHT]
            near_y = terms[a, BOTTOM] < terms[b, TOP] and terms[b, BOTTOM] < terms[a, TOP]
            if near_x and near_y:
                first, second = (a, b) if (kind[a], a) <= (kind[b], b) else (b, a)
                found.add((first, second))
    return found


def random_scene(seed: int, count: int = 150) -> p2.World:
    """Circles and boxes of many sizes, fast and slow, some asleep, fixed, kinematic or
    switched off, a long fixed ground box and two planes."""
    rng = np.random.default_rng(seed)
    world = p2.World()
    world.add(p2.Plane(normal=(0.0, 1.0), point=(0.0, -8.0)))
    world.add(p2.Plane(normal=(1.0, 0.2), point=(-9.0, 0.0)))
    world.add(p2.Box(position=(0.0, -7.0), width=60.0, height=0.5, fixed=True))
    for i in range(count):
        common = {
            "position": rng.uniform(-6.0, 6.0, 2),
            "angle": rng.uniform(0, 3),
            "fixed": bool(i % 11 == 0),
            "kinematic": bool(i % 13 == 0 and i % 11),
        }
        if not common["fixed"]:
            common["velocity"] = rng.normal(0.0, 10.0, 2)
        size = rng.uniform(0.05, 0.8)
        if i % 2:
            body = world.add(p2.Circle(radius=size, **common))
        else:
            body = world.add(p2.Box(width=size, height=rng.uniform(0.05, 2.0), **common))
        if i % 7 == 3:
            body.enabled = False
    world.stop(None) if seed % 2 else None
    rows = world.bodies
    for body in rows[3::5]:
        if not body.fixed:
            body.wake()
    return world


# Scenes on either side of broadphase.SMALL_WORLD slots: swept in place, or in sweep order.
SIZES = pytest.mark.parametrize("count", [40, 150], ids=["small world", "large world"])


def _slots_check(world: p2.World, count: int) -> None:
    small = world.state.body.shape[1] <= broadphase.SMALL_WORLD
    assert small == (count == 40)


@SIZES
@pytest.mark.parametrize("seed", range(6))
def test_pairs_are_exactly_the_overlapping_boxes_that_can_touch(seed, count):
    """The sweep finds exactly the pairs a test of every pair finds, once each, A and B
    ordered by kind, and in canonical order."""
    world = random_scene(seed, count)
    _slots_check(world, count)
    pairs = candidate_pairs(world)
    assert {tuple(p) for p in pairs.tolist()} == brute_force(world)
    assert len({tuple(p) for p in pairs.tolist()}) == len(pairs)
    kind = world.layout.kind
    assert np.all((kind[pairs[:, 0]] < kind[pairs[:, 1]]) | (pairs[:, 0] < pairs[:, 1]))
    keys = pairs[:, 0] * 10_000 + pairs[:, 1]
    assert np.all(np.diff(keys) > 0)


@SIZES
@pytest.mark.parametrize("awake", [0, 1, 20, -2])
def test_a_resting_scene_pairs_only_around_what_moves(awake, count):
    """Everything asleep but one body (or none): the sweep passes over the boxes that do
    not move unless a moving box starts within their reach, and still finds exactly the
    pairs a test of every pair finds (those with the moving body, and none else)."""
    world = random_scene(2, count)
    _slots_check(world, count)
    world.stop(None)
    movable = [b for b in world.bodies if not isinstance(b, p2.Plane) and not b.fixed]
    chosen = [b for b in movable if b.enabled][awake]
    chosen.wake()
    pairs = {tuple(p) for p in candidate_pairs(world).tolist()}
    assert pairs == brute_force(world) and pairs
    assert all(chosen.slot in pair for pair in pairs)


@SIZES
def test_pairs_do_not_depend_on_the_remembered_order(count):
    """The sweep keeps its sorted order between steps; any order gives the same pairs in
    the same order (so a restored world solves its contacts in the same order)."""
    world = random_scene(1, count)
    _slots_check(world, count)
    reference = candidate_pairs(world)
    rng = np.random.default_rng(0)
    for _ in range(5):
        world.state.body_i[0, :, SAP_ORDER] = rng.permutation(world.state.body.shape[1])
        np.testing.assert_array_equal(candidate_pairs(world), reference)


def _rain(count: int, seed: int = 0) -> p2.World:
    """``count`` small circles and boxes spread over a wide floor, falling."""
    rng = np.random.default_rng(seed)
    world = p2.World(sleeping=False)
    world.add(p2.Plane())
    width = count * 0.6  # keeps the density the same for every count
    for i in range(count):
        position = (rng.uniform(-width / 2, width / 2), rng.uniform(0.5, 6.0))
        if i % 2:
            world.add(p2.Circle(position=position, radius=0.2))
        else:
            world.add(p2.Box(position=position, width=0.4, height=0.3, angle=rng.uniform(0, 3)))
    return world


def test_pair_count_grows_linearly_with_scene_size():
    """At the same density, 4x the bodies gives about 4x the candidate pairs (not 16x)."""
    counts = {}
    for count in (250, 1000):
        world = _rain(count)
        for _ in range(90):
            world.step(DT)
        counts[count] = len(candidate_pairs(world))
        assert counts[count] > count  # every body is paired with the ground at least
    assert counts[1000] / counts[250] < 6.0


@pytest.mark.parametrize("angle", [0.0, 0.5, 2.0, -1.2])
def test_a_polygons_box_is_its_turned_outlines_box(angle):
    """A long plank's broadphase box is the box round its corners as turned now (and its
    rounding), grown by the step's reach, not the square round its bounding circle: a
    40 m paddle would otherwise pair with everything within 20 m of its centre."""
    world = p2.World(gravity=(0.0, 0.0))
    plank = world.add(
        p2.Polygon(
            vertices=[(-20.0, -0.25), (20.0, -0.25), (20.0, 0.25), (-20.0, 0.25)], radius=0.1
        )
    )
    plank.position, plank.angle = (3.0, -1.0), angle
    terms = step_terms(world)
    corners = plank.world_vertices()
    grow = terms[plank.slot, LEFT] - (corners[:, 0].min() - 0.1)
    assert grow <= 0.0
    reach = -grow
    np.testing.assert_allclose(terms[plank.slot, LEFT], corners[:, 0].min() - 0.1 - reach)
    np.testing.assert_allclose(terms[plank.slot, RIGHT], corners[:, 0].max() + 0.1 + reach)
    np.testing.assert_allclose(terms[plank.slot, BOTTOM], corners[:, 1].min() - 0.1 - reach)
    np.testing.assert_allclose(terms[plank.slot, TOP], corners[:, 1].max() + 0.1 + reach)
    assert reach < 0.1  # at rest: the speculative margin alone
    # A ball 5 m above the flat plank's middle, well inside its bounding circle, is no
    # candidate; turned, the plank's box reaches it.
    ball = world.add(p2.Circle(radius=0.5, position=(3.0, 4.0)))
    paired = {tuple(sorted(pair)) for pair in candidate_pairs(world)}
    boxes_meet = corners[:, 1].max() + 0.1 + reach > 3.5 - reach
    assert ((plank.slot, ball.slot) in paired) == boxes_meet
    assert boxes_meet == (angle != 0.0)
