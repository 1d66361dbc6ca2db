"""The polygon pairs of the narrowphase alone (``core.outlines``), on hand-built outlines:
the conventions every pair keeps (a unit normal from A to B, one world point per contact,
midway between the surfaces, features in order), separations against a signed distance
written here independently, speculative points that never claim more room than there
is, Box2D's vertex-vertex case for rounded corners, a box read from its half sizes as
the outline of its corners, and the dispatch by the registry.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from impulse2d import geometry
from impulse2d.core import narrowphase
from impulse2d.core.narrowphase import (
    BOX_POLYGON,
    CIRCLE_POLYGON,
    PAIRS,
    POLYGON_PLANE,
    POLYGON_POLYGON,
)
from impulse2d.core.state import BOX, CIRCLE, PLANE, POLYGON
from impulse2d.polygons import capsule_unit_moment, outline_row

NO_ROW = np.zeros(0)
POLYGON_PAIRS = (CIRCLE_POLYGON, BOX_POLYGON, POLYGON_POLYGON, POLYGON_PLANE)


# -- shapes: (pose tuple, outline row, local vertices, radius) ----------------------------------
def pose(x, y, angle=0.0, hw=0.0, hh=0.0, normal=(0.0, 0.0)):
    c, s = math.cos(angle), math.sin(angle)
    return narrowphase.shape(x, y, c, s, hw, hh, 0.0, 0.0, normal[0], normal[1])


def polygon(x, y, vertices, radius=0.0, angle=0.0):
    points = geometry.check_polygon(vertices, radius)
    mass = geometry.mass(points, radius)
    local = points - np.array(mass.centroid)
    return pose(x, y, angle), outline_row(local, radius, mass.moment / mass.area), local, radius


def placed(vertices, radius=0.0):
    """A polygon at the centroid of ``vertices`` (world points), unturned."""
    centroid = geometry.mass(geometry.check_polygon(vertices, radius), radius).centroid
    return polygon(*centroid, vertices, radius)


def capsule(x, y, length, radius, angle=0.0):
    ends = np.array([[-0.5 * length, 0.0], [0.5 * length, 0.0]])
    row = outline_row(ends, radius, capsule_unit_moment(length, radius))
    return pose(x, y, angle), row, ends, radius


def square(x, y, side, angle=0.0, radius=0.0):
    h = 0.5 * side
    return polygon(x, y, [(h, h), (-h, h), (-h, -h), (h, -h)], radius, angle)


def box(x, y, hw, hh, angle=0.0):
    corners = np.array([(hw, hh), (-hw, hh), (-hw, -hh), (hw, -hh)])
    return pose(x, y, angle, hw, hh), NO_ROW, corners, 0.0


def disc(x, y, r):
    return pose(x, y, 0.0, r, r), NO_ROW, None, r


def plane(x, y, nx, ny):
    length = math.hypot(nx, ny)
    return pose(x, y, normal=(nx / length, ny / length)), NO_ROW, None, 0.0


def call(kind, a, b, margin, tag=0.0):
    return PAIRS[kind][2](a[0], b[0], a[1], b[1], margin, tag)


def kept_points(manifold) -> list[tuple]:
    return [manifold[3 + k] for k in range(4) if manifold[0] & (1 << k)]


# -- an independent signed distance -------------------------------------------------------------
def world_vertices(shape) -> np.ndarray:
    p, _, local, _ = shape
    c, s = p[2], p[3]
    return local @ np.array([[c, s], [-s, c]]) + [p[0], p[1]]


def _segment_distance(q, a, b) -> float:
    t = np.clip((q - a) @ (b - a) / ((b - a) @ (b - a)), 0.0, 1.0)
    return float(np.linalg.norm(q - a - t * (b - a)))


def distance(shape, kind, q) -> float:
    """Signed distance from world point ``q`` to the shape's surface (< 0 inside)."""
    q = np.asarray(q, float)
    p, _, _, radius = shape
    if kind == CIRCLE:
        return float(np.hypot(q[0] - p[0], q[1] - p[1]) - radius)
    if kind == PLANE:
        return float((q - [p[0], p[1]]) @ [p[8], p[9]])
    v = world_vertices(shape)
    n = len(v)
    nearest = min(_segment_distance(q, v[k], v[(k + 1) % n]) for k in range(n))
    # Inside the core: left of every edge (counter-clockwise).
    edges = np.roll(v, -1, axis=0) - v
    inside = n > 2 and all(
        edges[k, 0] * (q[1] - v[k, 1]) - edges[k, 1] * (q[0] - v[k, 0]) > 0 for k in range(n)
    )
    return (-nearest if inside else nearest) - radius


def core_distance(a, b) -> float:
    """Distance between two disjoint convex cores: the least vertex-to-edge distance."""
    va, vb = world_vertices(a), world_vertices(b)
    best = math.inf
    for one, other in ((va, vb), (vb, va)):
        m = len(other)
        for q in one:
            for k in range(m):
                best = min(best, _segment_distance(q, other[k], other[(k + 1) % m]))
    return best


def check_manifold(kind, a, b, manifold, on_surfaces=True) -> None:
    """A unit normal, one world point per contact (A + rA = B + rB), and, for sharp
    shapes, that point midway: P - (s/2) n on A's surface and P + (s/2) n on B's."""
    kind_a, kind_b, _ = PAIRS[kind]
    n = np.array([manifold[1], manifold[2]])
    assert np.linalg.norm(n) == pytest.approx(1.0, abs=1e-12)
    for rax, ray, rbx, rby, sep, _ in kept_points(manifold):
        on_a = np.array([a[0][0] + rax, a[0][1] + ray])
        np.testing.assert_allclose(on_a, [b[0][0] + rbx, b[0][1] + rby], atol=1e-12)
        if on_surfaces:
            assert distance(a, kind_a, on_a - 0.5 * sep * n) == pytest.approx(0.0, abs=1e-9)
            assert distance(b, kind_b, on_a + 0.5 * sep * n) == pytest.approx(0.0, abs=1e-9)


# -- hand-built cases -----------------------------------------------------------------------------
def test_a_square_resting_on_a_box_has_two_points_at_its_lower_corners():
    """A unit square 1 cm into a wide box below it: two points at x = -/+0.5, separation
    -0.01, normal from A (the box) up to B (the square), features in order."""
    ground = box(0.0, -0.5, 3.0, 0.5)
    block = square(0.0, 0.49, 1.0)
    manifold = call(BOX_POLYGON, ground, block, 0.02)
    points = kept_points(manifold)
    assert len(points) == 2
    np.testing.assert_allclose([manifold[1], manifold[2]], [0.0, 1.0], atol=1e-12)
    for point in points:
        assert point[4] == pytest.approx(-0.01, abs=1e-12)
    xs = sorted(ground[0][0] + p[0] for p in points)
    np.testing.assert_allclose(xs, [-0.5, 0.5], atol=1e-12)
    assert [p[5] for p in points] == sorted(p[5] for p in points)
    check_manifold(BOX_POLYGON, ground, block, manifold)


def test_a_capsule_lying_on_a_plane_touches_at_both_ends():
    """A capsule (length 2, radius 0.25) with its axis 0.3 m above the ground: two
    points below its segment's ends, separation 0.05."""
    ground = plane(0.0, 0.0, 0.0, 1.0)
    rod = capsule(1.0, 0.3, 2.0, 0.25)
    manifold = call(POLYGON_PLANE, rod, ground, 0.1)
    points = kept_points(manifold)
    assert len(points) == 2
    np.testing.assert_allclose([manifold[1], manifold[2]], [0.0, -1.0], atol=1e-12)
    for point in points:
        assert point[4] == pytest.approx(0.05, abs=1e-12)
    np.testing.assert_allclose(sorted(1.0 + p[0] for p in points), [0.0, 2.0], atol=1e-12)
    check_manifold(POLYGON_PLANE, rod, ground, manifold, on_surfaces=False)


def test_a_disc_beside_a_capsule_and_beyond_its_end():
    """Beside the capsule the normal is the side's and the gap its distance; beyond an
    end, along the line from the end's centre (the rounded cap)."""
    rod = capsule(0.0, 0.0, 2.0, 0.25)
    side = call(CIRCLE_POLYGON, disc(0.3, 1.0, 0.5), rod, 1.0)
    np.testing.assert_allclose([side[1], side[2]], [0.0, -1.0], atol=1e-12)
    assert side[3][4] == pytest.approx(1.0 - 0.25 - 0.5, abs=1e-12)
    end = call(CIRCLE_POLYGON, disc(1.0 + 0.6, 0.8, 0.5), rod, 1.0)
    np.testing.assert_allclose([end[1], end[2]], [-0.6, -0.8], atol=1e-12)
    assert end[3][4] == pytest.approx(1.0 - 0.25 - 0.5, abs=1e-12)
    for a, manifold in ((disc(0.3, 1.0, 0.5), side), (disc(1.6, 0.8, 0.5), end)):
        check_manifold(CIRCLE_POLYGON, a, rod, manifold)


def test_rounded_squares_corner_to_corner_meet_along_the_diagonal():
    """Two rounded squares apart corner to corner: one point, the normal along the line
    between the corners (not an edge's normal), the gap the corners' distance less both
    radii (Box2D's vertex-vertex case)."""
    a = square(0.0, 0.0, 1.0, radius=0.1)
    b = square(1.5, 1.5, 1.0, radius=0.1)
    manifold = call(POLYGON_POLYGON, a, b, 1.0)
    assert len(kept_points(manifold)) == 1
    np.testing.assert_allclose([manifold[1], manifold[2]], [math.sqrt(0.5)] * 2, atol=1e-12)
    assert manifold[3][4] == pytest.approx(math.sqrt(2.0) * 0.5 - 0.2, abs=1e-12)
    check_manifold(POLYGON_POLYGON, a, b, manifold)


def test_a_triangle_point_down_on_a_square_has_one_point_at_its_tip():
    """A triangle balanced on its tip 2 mm above a square's top: one point (the other
    incident end is clipped far above), separation 0.002, on the tip."""
    base = square(0.0, 0.0, 2.0)
    tip_height = 1.002
    tri = placed([(0.0, tip_height), (0.5, tip_height + 1.0), (-0.5, tip_height + 1.0)])
    manifold = call(POLYGON_POLYGON, base, tri, 0.01)
    points = kept_points(manifold)
    assert len(points) == 1
    assert points[0][4] == pytest.approx(0.002, abs=1e-12)
    check_manifold(POLYGON_POLYGON, base, tri, manifold)


def test_a_box_as_a_polygon_pair_matches_the_outline_of_its_corners():
    """``polygon_polygon`` with a box (an empty row: its corners from its half sizes) gives
    bitwise what it gives with the box written out as a four-vertex outline."""
    rng = np.random.default_rng(3)
    for _ in range(100):
        hw, hh, angle = *rng.uniform(0.1, 1.0, 2), rng.uniform(-np.pi, np.pi)
        x, y = rng.uniform(-1.5, 1.5, 2)
        as_box = box(x, y, hw, hh, angle)
        corners = np.array([(hw, hh), (-hw, hh), (-hw, -hh), (hw, -hh)])
        written = (pose(x, y, angle), outline_row(corners, 0.0, 0.0), corners, 0.0)
        other = polygon(0.0, 0.0, [(0.0, -0.6), (0.7, 0.1), (0.1, 0.6), (-0.5, 0.2)], 0.0, 0.4)
        assert call(BOX_POLYGON, as_box, other, 0.3) == call(POLYGON_POLYGON, written, other, 0.3)


def test_two_boxes_stacked_as_polygons_give_box_box_separations():
    """A box on a box, apart or overlapping by up to 2 cm: the polygon pair and ``box_box``
    keep the same points with the same separations (their feature numbering differs)."""
    rng = np.random.default_rng(5)
    compared = 0
    for _ in range(200):
        hw_a, hh_a, hw_b, hh_b = rng.uniform(0.2, 1.0, 4)
        a = box(0.0, 0.0, hw_a, hh_a)
        b = box(rng.uniform(-0.5, 0.5) * hw_a, hh_a + hh_b + rng.uniform(-0.02, 0.02), hw_b, hh_b)
        mine = call(BOX_POLYGON, a, b, 0.05)
        theirs = narrowphase.box_box(a[0], b[0], NO_ROW, NO_ROW, 0.05, 0.0)
        if bin(mine[0]).count("1") == 2 and bin(theirs[0]).count("1") == 2:
            compared += 1
            assert sorted(p[4] for p in kept_points(mine)) == pytest.approx(
                sorted(p[4] for p in kept_points(theirs)), abs=1e-12
            )
    assert compared > 20


# -- random outlines: the conventions everywhere --------------------------------------------------
def _random_outline(rng, x, y, rounded):
    n = int(rng.integers(3, 9))
    angles = np.sort(rng.uniform(0.0, 2 * np.pi, n))
    while np.min(np.diff(np.append(angles, angles[0] + 2 * np.pi))) < 0.3:
        angles = np.sort(rng.uniform(0.0, 2 * np.pi, n))
    radii = rng.uniform(0.3, 0.8, n)
    vertices = np.column_stack([radii * np.cos(angles), radii * np.sin(angles)])
    hull = _convex_hull(vertices)
    radius = rng.uniform(0.0, 0.2) if rounded else 0.0
    if rng.random() < 0.25:
        return capsule(x, y, rng.uniform(0.2, 1.2), max(radius, 0.05), rng.uniform(-np.pi, np.pi))
    return polygon(x, y, hull, radius, rng.uniform(-np.pi, np.pi))


def _convex_hull(points: np.ndarray) -> np.ndarray:
    """Andrew's monotone chain, counter-clockwise, collinear points dropped."""
    pts = sorted(map(tuple, points))

    def half(seq):
        out: list = []
        for p in seq:
            while (
                len(out) >= 2
                and (
                    (out[-1][0] - out[-2][0]) * (p[1] - out[-2][1])
                    - (out[-1][1] - out[-2][1]) * (p[0] - out[-2][0])
                )
                <= 1e-9
            ):
                out.pop()
            out.append(p)
        return out

    lower, upper = half(pts), half(reversed(pts))
    hull = np.array(lower[:-1] + upper[:-1])
    edges = np.roll(hull, -1, axis=0) - hull
    keep = np.hypot(edges[:, 0], edges[:, 1]) > 0.02
    return hull[keep] if keep.sum() >= 3 else np.array([(0.5, 0), (0, 0.5), (-0.5, -0.5)])


def _random_pair(kind, rng, rounded):
    kind_a, kind_b, _ = PAIRS[kind]

    def make(k, centre):
        if k == CIRCLE:
            return disc(*centre, rng.uniform(0.1, 0.8))
        if k == BOX:
            return box(*centre, *rng.uniform(0.1, 0.8, 2), rng.uniform(-np.pi, np.pi))
        if k == PLANE:
            angle = rng.uniform(-np.pi, np.pi)
            return plane(*centre, math.cos(angle), math.sin(angle))
        return _random_outline(rng, *centre, rounded)

    return make(kind_a, (0.0, 0.0)), make(kind_b, rng.uniform(-1.5, 1.5, 2))


@pytest.mark.parametrize("kind", POLYGON_PAIRS)
def test_random_sharp_outlines_obey_the_conventions(kind):
    """300 random placements a pair (sharp polygons and boxes, overlapping or not): a unit
    normal, A + rA = B + rB, each point midway between the surfaces (1e-9), points in
    feature order."""
    rng = np.random.default_rng(kind)
    found = 0
    for _ in range(300):
        a, b = _random_pair(kind, rng, rounded=False)
        if any(s[2] is not None and len(s[2]) == 2 for s in (a, b)):
            continue  # capsules are rounded: the next test
        manifold = call(kind, a, b, 0.3, float(rng.integers(100)))
        if manifold[0]:
            found += 1
            check_manifold(kind, a, b, manifold)
            features = [p[5] for p in kept_points(manifold)]
            assert features == sorted(features)
    assert found > 50


@pytest.mark.parametrize("kind", (CIRCLE_POLYGON, BOX_POLYGON, POLYGON_POLYGON))
def test_speculative_points_never_claim_more_room_than_there_is(kind):
    """For shapes apart (rounded or not, capsules too), the smallest separation a manifold
    reports is at most the true gap between them (cores' distance less the radii), so a
    speculative contact never lets one pass into the other; where the closest features
    are a face and a vertex, it is the gap (1e-9)."""
    rng = np.random.default_rng(10 + kind)
    apart = 0
    for _ in range(400):
        a, b = _random_pair(kind, rng, rounded=True)
        if a[2] is None:  # a disc: its core is its centre
            core = distance((b[0], b[1], b[2], 0.0), POLYGON, (a[0][0], a[0][1]))
            overlap = core < 0.0
        else:
            core, overlap = (
                core_distance(a, b),
                not _separated(world_vertices(a), world_vertices(b)),
            )
        gap = core - a[3] - b[3]
        if overlap or gap <= 1e-6:
            continue
        apart += 1
        manifold = call(kind, a, b, gap + 0.5)
        separations = [p[4] for p in kept_points(manifold)]
        assert separations, "a pair within the margin must have a point"
        assert min(separations) <= gap + 1e-9
    assert apart > 100


def _separated(va: np.ndarray, vb: np.ndarray) -> bool:
    """Whether an edge normal of either convex core separates them (exact for convex
    shapes: disjoint ones have a separating edge normal)."""
    for v in (va, vb):
        edges = np.roll(v, -1, axis=0) - v
        for normal in np.column_stack([edges[:, 1], -edges[:, 0]]):
            if (va @ normal).max() < (vb @ normal).min() or (vb @ normal).max() < (
                va @ normal
            ).min():
                return True
    return False


@pytest.mark.parametrize("kind", POLYGON_PAIRS)
def test_turning_the_scene_turns_the_manifold(kind):
    """The whole pair turned about the origin: normals and anchors turn with it, and
    separations and features stay (1e-9)."""
    rng = np.random.default_rng(20 + kind)
    for _ in range(50):
        a, b = _random_pair(kind, rng, rounded=True)
        phi = rng.uniform(-np.pi, np.pi)
        first = call(kind, a, b, 0.3)
        turned = call(kind, _turned(a, phi), _turned(b, phi), 0.3)
        assert first[0] == turned[0]
        c, s = math.cos(phi), math.sin(phi)
        n = np.array([first[1], first[2]])
        if not first[0]:
            continue
        np.testing.assert_allclose(
            [turned[1], turned[2]], [c * n[0] - s * n[1], s * n[0] + c * n[1]], atol=1e-9
        )
        for p, q in zip(kept_points(first), kept_points(turned), strict=True):
            assert q[4] == pytest.approx(p[4], abs=1e-9) and q[5] == p[5]
            np.testing.assert_allclose(
                [q[0], q[1]], [c * p[0] - s * p[1], s * p[0] + c * p[1]], atol=1e-9
            )


def _turned(shape, phi):
    p, row, local, radius = shape
    c, s = math.cos(phi), math.sin(phi)
    x, y = c * p[0] - s * p[1], s * p[0] + c * p[1]
    angle = math.atan2(p[3], p[2]) + phi
    nx, ny = c * p[8] - s * p[9], s * p[8] + c * p[9]
    return pose(x, y, angle, p[4], p[5], (nx, ny)), row, local, radius


@pytest.mark.parametrize("kind", POLYGON_PAIRS)
def test_collide_dispatches_as_the_registry_says(kind):
    rng = np.random.default_rng(30 + kind)
    for _ in range(30):
        a, b = _random_pair(kind, rng, rounded=True)
        expected = call(kind, a, b, 0.3, 5.0)
        assert narrowphase.collide(kind, a[0], b[0], a[1], b[1], 0.3, 5.0) == expected


@settings(max_examples=60, deadline=None)
@given(shift=st.floats(-0.002, 0.002), lift=st.floats(0.0, 0.002))
def test_feature_ids_stay_when_a_resting_shape_moves_a_little(shift, lift):
    """A hexagon resting on a box keeps its two points' feature ids when it moves by up to
    2 mm (warm starting matches points by them)."""
    ground = box(0.0, -0.5, 3.0, 0.5)
    hexagon = [(math.cos(t), math.sin(t)) for t in np.arange(6) * np.pi / 3]
    rest = polygon(0.0, math.cos(np.pi / 6) * 1.0 - 0.001, hexagon)
    moved = polygon(shift, rest[0][1] + lift, hexagon)
    features = [p[5] for p in kept_points(call(BOX_POLYGON, ground, rest, 0.02))]
    assert len(features) == 2
    assert [p[5] for p in kept_points(call(BOX_POLYGON, ground, moved, 0.02))] == features
