"""The narrowphase stage alone: each pair function on hand-built shapes (Box2D's collision
tests): the normal points from A to B and is a unit vector, separations are the hand-computed
gaps, the anchors name one world point midway between the two surfaces, the margin decides
what is kept, feature ids are stable, and ``collide`` dispatches exactly as ``PAIRS`` says.

Shapes are tuples built by ``narrowphase.shape``; manifolds are ``(kept, nx, ny, p0..p3)``
with points ``(rax, ray, rbx, rby, separation, feature)``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import impulse2d as p2
from impulse2d.core import broadphase, integrate, narrowphase, workspace
from impulse2d.core.narrowphase import (
    BOX_BOX,
    BOX_PLANE,
    CIRCLE_BOX,
    CIRCLE_CIRCLE,
    CIRCLE_PLANE,
    PAIRS,
)
from impulse2d.core.state import BOX, CIRCLE, PLANE, POLYGON

NO_ROW = np.zeros(0)  # the outline row of every shape but a polygon (outlines.py)
# The tutorial's pairs; the polygon pairs have tests of their own (test_stage_outlines.py).
TUTORIAL_PAIRS = (CIRCLE_CIRCLE, CIRCLE_BOX, BOX_BOX, CIRCLE_PLANE, BOX_PLANE)

DT = 1 / 60
HALF_DIAGONAL = math.sqrt(0.5)  # of a unit square
C01, S01 = math.cos(0.01), math.sin(0.01)  # a unit box turned 0.01 rad: lowest corner 0.5 (c + s)


# -- shapes and readouts --------------------------------------------------------------------
def circle(x, y, r, v=(0.0, 0.0)):
    return narrowphase.shape(x, y, 1.0, 0.0, r, r, v[0], v[1], 0.0, 0.0)


def box(x, y, hw, hh, angle=0.0, v=(0.0, 0.0)):
    c, s = math.cos(angle), math.sin(angle)
    return narrowphase.shape(x, y, c, s, hw, hh, v[0], v[1], 0.0, 0.0)


def plane(x, y, nx, ny):
    length = math.hypot(nx, ny)
    return narrowphase.shape(x, y, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, nx / length, ny / length)


def kept_points(manifold) -> list[tuple]:
    """The points whose bit is set in ``kept``, in manifold order."""
    return [manifold[3 + k] for k in range(4) if manifold[0] & (1 << k)]


def normal_of(manifold) -> np.ndarray:
    return np.array([manifold[1], manifold[2]])


def distance(shape, kind, q) -> float:
    """Signed distance from point ``q`` to the surface of ``shape`` (< 0 inside), written
    independently of the engine."""
    q = np.asarray(q, float)
    centre = np.array([shape[0], shape[1]])
    if kind == CIRCLE:
        return float(np.linalg.norm(q - centre) - shape[4])
    if kind == PLANE:
        return float((q - centre) @ np.array([shape[8], shape[9]]))
    c, s = shape[2], shape[3]
    d = q - centre
    local = np.abs([c * d[0] + s * d[1], -s * d[0] + c * d[1]]) - [shape[4], shape[5]]
    return float(np.linalg.norm(np.maximum(local, 0.0)) + min(max(local[0], local[1]), 0.0))


def check_manifold(kind, a, b, manifold, same_point=True) -> None:
    """What every manifold must satisfy: a unit normal; for each point, ``P - (s/2) n`` on
    A's surface and ``P + (s/2) n`` on B's, P = A + rA (and = B + rB, the same world point)."""
    kind_a, kind_b, _ = PAIRS[kind]
    n = normal_of(manifold)
    assert np.linalg.norm(n) == pytest.approx(1.0, abs=1e-12)
    for rax, ray, rbx, rby, sep, _ in kept_points(manifold):
        on_a = np.array([a[0] + rax, a[1] + ray])
        on_b = np.array([b[0] + rbx, b[1] + rby])
        if same_point:
            np.testing.assert_allclose(on_a, on_b, atol=1e-12)
        assert distance(a, kind_a, on_a - 0.5 * sep * n) == pytest.approx(0.0, abs=1e-12)
        assert distance(b, kind_b, on_b + 0.5 * sep * n) == pytest.approx(0.0, abs=1e-12)


# Each pair with B to the right of A (a plane B: its solid side is x >= 1.5).
RIGHTWARD = {
    CIRCLE_CIRCLE: (circle(0, 0, 0.5), circle(1.1, 0.0, 0.5)),
    CIRCLE_BOX: (circle(0, 0, 0.5), box(1.0, 0.0, 0.4, 0.8)),
    BOX_BOX: (box(0, 0, 0.5, 0.5), box(1.05, 0.1, 0.5, 0.3)),
    CIRCLE_PLANE: (circle(0, 0, 0.5), plane(0.6, 3.0, -1.0, 0.0)),
    BOX_PLANE: (box(0, 0, 0.5, 0.5), plane(0.55, -2.0, -1.0, 0.0)),
}


@pytest.mark.parametrize("kind", sorted(RIGHTWARD))
def test_normal_points_from_a_to_b(kind):
    """B to the right of A: the normal is (+1, 0) to 1e-12 for every pair function, and the
    manifold satisfies the anchor and surface conventions."""
    a, b = RIGHTWARD[kind]
    manifold = PAIRS[kind][2](a, b, NO_ROW, NO_ROW, 0.2, 0.0)
    assert manifold[0] != 0
    np.testing.assert_allclose(normal_of(manifold), [1.0, 0.0], atol=1e-12)
    check_manifold(kind, a, b, manifold)


def _rotated(shape, phi):
    """The shape turned by ``phi`` about the origin (position, orientation, velocity,
    plane normal)."""
    c, s = math.cos(phi), math.sin(phi)
    x, y, sc, ss, hw, hh, vx, vy, nx, ny = shape
    return narrowphase.shape(
        c * x - s * y, s * x + c * y, c * sc - s * ss, s * sc + c * ss, hw, hh,
        c * vx - s * vy, s * vx + c * vy, c * nx - s * ny, s * nx + c * ny,
    )  # fmt: skip


@pytest.mark.parametrize("phi", [0.3, 1.0, 2.5, -2.0])
@pytest.mark.parametrize("kind", sorted(RIGHTWARD))
def test_turning_the_scene_turns_the_manifold(kind, phi):
    """Turning both shapes by phi about the origin turns the normal and anchors by phi and
    leaves kept mask, separations and feature ids unchanged (1e-12)."""
    a, b = RIGHTWARD[kind]
    function = PAIRS[kind][2]
    ref = function(a, b, NO_ROW, NO_ROW, 0.2, 0.0)
    turned = function(_rotated(a, phi), _rotated(b, phi), NO_ROW, NO_ROW, 0.2, 0.0)
    c, s = math.cos(phi), math.sin(phi)
    turn = np.array([[c, -s], [s, c]])
    assert turned[0] == ref[0]
    np.testing.assert_allclose(normal_of(turned), turn @ normal_of(ref), atol=1e-12)
    for p, q in zip(kept_points(ref), kept_points(turned), strict=True):
        np.testing.assert_allclose(q[:2], turn @ p[:2], atol=1e-12)
        np.testing.assert_allclose(q[2:4], turn @ p[2:4], atol=1e-12)
        assert q[4] == pytest.approx(p[4], abs=1e-12)
        assert q[5] == p[5]


# -- separations against hand-computed geometry ----------------------------------------------
SEPARATIONS = [
    # (kind, A, B, expected separation of the deepest point), touching / gap / overlap
    (CIRCLE_CIRCLE, circle(0, 0, 0.5), circle(0.8, 0, 0.3), 0.0),
    (CIRCLE_CIRCLE, circle(0, 0, 0.5), circle(0, 1.0, 0.3), 0.2),
    (CIRCLE_CIRCLE, circle(0, 0, 0.5), circle(-0.36, 0.48, 0.3), -0.2),
    (CIRCLE_BOX, circle(0, 0, 0.5), box(0.9, 0, 0.4, 0.6), 0.0),
    (CIRCLE_BOX, circle(0, 0, 0.5), box(1.2, 0, 0.4, 0.6, angle=math.pi / 2), 0.1),
    (CIRCLE_BOX, circle(0, 0, 0.5), box(1.2, 0, 0.5, 0.5, angle=math.pi / 4), 0.7 - HALF_DIAGONAL),
    (CIRCLE_BOX, circle(0.9, 0, 0.2), box(0, 0, 1.0, 0.5), -0.3),  # centre inside the box
    (BOX_BOX, box(0, 0, 1.0, 0.5), box(0.2, 1.0, 0.5, 0.5), 0.0),
    (BOX_BOX, box(0, 0, 1.0, 0.5), box(0.2, 1.05, 0.5, 0.5), 0.05),
    (BOX_BOX, box(0, 0, 1, 0.5), box(0.2, 0.9, 0.5, 0.5, 0.01), 0.4 - 0.5 * (C01 + S01)),
    (BOX_BOX, box(0, 0, 1.0, 0.5), box(0, 1.2, 0.5, 0.5, math.pi / 4), 0.7 - HALF_DIAGONAL),
    (CIRCLE_PLANE, circle(3, 0.5, 0.5), plane(0, 0, 0, 1), 0.0),
    (CIRCLE_PLANE, circle(3, 0.45, 0.5), plane(0, 0, 0, 1), -0.05),
    (CIRCLE_PLANE, circle(1 + 0.6 * 0.6, 0.6 * 0.8, 0.5), plane(1, 0, 0.6, 0.8), 0.1),
    (BOX_PLANE, box(0, 0.5, 1.0, 0.5), plane(0, 0, 0, 1), 0.0),
    (BOX_PLANE, box(0, 0.45, 1.0, 0.5), plane(0, 0, 0, 1), -0.05),
    (BOX_PLANE, box(0, 0.75, 0.5, 0.5, math.pi / 4), plane(0, 0, 0, 1), 0.75 - HALF_DIAGONAL),
]


@pytest.mark.parametrize(("kind", "a", "b", "expected"), SEPARATIONS)
def test_separation_is_the_hand_computed_gap(kind, a, b, expected):
    """The deepest point's separation is the gap between the shapes (0 touching, > 0 the
    distance, < 0 minus the depth; 45-degree boxes stand on a corner at y - half diagonal),
    to 1e-12; every point satisfies the anchor and surface conventions."""
    manifold = PAIRS[kind][2](a, b, NO_ROW, NO_ROW, 0.3, 7.0)
    points = kept_points(manifold)
    assert points
    assert min(p[4] for p in points) == pytest.approx(expected, abs=1e-12)
    check_manifold(kind, a, b, manifold)


def test_rotated_box_on_a_corner_has_one_point():
    """A unit box turned 45 degrees above the ground at height y has one point (corner 2,
    pointing down) with separation y - sqrt(1/2), at height separation / 2 above the plane,
    directly below the centre (1e-12); the other corners are out of the margin."""
    y = 0.72
    a, b = box(0.3, y, 0.5, 0.5, math.pi / 4), plane(0, 0, 0, 1)
    manifold = narrowphase.box_plane(a, b, NO_ROW, NO_ROW, 0.05, 0.0)
    assert manifold[0] == 1 << 2
    rax, ray, _, _, sep, feature = manifold[3 + 2]
    assert feature == 2
    assert sep == pytest.approx(y - HALF_DIAGONAL, abs=1e-12)
    np.testing.assert_allclose([a[0] + rax, a[1] + ray], [0.3, sep / 2], atol=1e-12)


def test_circle_plane_point_is_midway():
    """A disc of radius r at height r + g above a plane: separation g, the point straight
    below the centre at height g / 2, rA = (0, -(r + g/2)), normal (0, -1) (1e-12)."""
    r, g = 0.4, 0.06
    a, b = circle(2.0, r + g, r), plane(-5.0, 0.0, 0.0, 1.0)
    manifold = narrowphase.circle_plane(a, b, NO_ROW, NO_ROW, 0.1, 0.0)
    assert manifold[0] == 1
    np.testing.assert_allclose(normal_of(manifold), [0.0, -1.0], atol=1e-12)
    rax, ray, rbx, rby, sep, _ = manifold[3]
    assert sep == pytest.approx(g, abs=1e-12)
    np.testing.assert_allclose([rax, ray], [0.0, -(r + g / 2)], atol=1e-12)
    np.testing.assert_allclose([b[0] + rbx, b[1] + rby], [2.0, g / 2], atol=1e-12)


# -- the margin -----------------------------------------------------------------------------
GAP = 0.05
AT_GAP = {  # every point of each pair exactly GAP apart
    CIRCLE_CIRCLE: (circle(0, 0, 0.5), circle(0, 0.8 + GAP, 0.3)),
    CIRCLE_BOX: (circle(0, 0, 0.5), box(0.5 + GAP + 0.4, 0, 0.4, 0.6)),
    BOX_BOX: (box(0, 0, 1.0, 0.5), box(0.2, 1.0 + GAP, 0.5, 0.5)),
    CIRCLE_PLANE: (circle(0, 0.5 + GAP, 0.5), plane(0, 0, 0, 1)),
    BOX_PLANE: (box(0, 0.5 + GAP, 1.0, 0.5), plane(0, 0, 0, 1)),
}


@pytest.mark.parametrize("kind", sorted(AT_GAP))
def test_margin_keeps_points_closer_than_it(kind):
    """Shapes 5 cm apart: a margin 1e-9 above the gap keeps every point of the pair, a
    margin 1e-9 below keeps none (kept when separation < margin)."""
    a, b = AT_GAP[kind]
    function = PAIRS[kind][2]
    above, below = (
        function(a, b, NO_ROW, NO_ROW, GAP + 1e-9, 0.0),
        function(a, b, NO_ROW, NO_ROW, GAP - 1e-9, 0.0),
    )
    expected = {BOX_BOX: 2, BOX_PLANE: 2}.get(kind, 1)
    assert len(kept_points(above)) == expected
    assert all(p[4] == pytest.approx(GAP, abs=1e-12) for p in kept_points(above))
    assert below[0] == 0


# -- box against plane ----------------------------------------------------------------------
@pytest.mark.parametrize("tilt", [0.0, 0.4, -1.1])
def test_resting_box_has_its_two_lower_corners(tilt):
    """A box resting flat on a plane (also a tilted plane, the box turned to match) gives
    exactly corners 2 (-,-) and 3 (+,-), in that order, at the box's lower corners, with
    separation 0 (1e-12)."""
    hw, hh = 0.8, 0.3
    n = np.array([-math.sin(tilt), math.cos(tilt)])
    centre = np.array([0.4, -0.2]) + 0.25 * np.array([n[1], -n[0]]) + hh * n
    a, b = box(*centre, hw, hh, tilt), plane(0.4, -0.2, *n)
    manifold = narrowphase.box_plane(a, b, NO_ROW, NO_ROW, 0.02, 0.0)
    assert manifold[0] == (1 << 2) | (1 << 3)
    np.testing.assert_allclose(normal_of(manifold), -n, atol=1e-12)
    c, s = math.cos(tilt), math.sin(tilt)
    for k, local in ((2, (-hw, -hh)), (3, (hw, -hh))):
        rax, ray, _, _, sep, feature = manifold[3 + k]
        assert feature == k
        assert sep == pytest.approx(0.0, abs=1e-12)
        corner = (c * local[0] - s * local[1], s * local[0] + c * local[1])
        np.testing.assert_allclose([rax, ray], corner, atol=1e-12)
    check_manifold(BOX_PLANE, a, b, manifold)


def _corners_reaching_plane(angle, height, spin, dt) -> set[int]:
    """Corners of a free box (hw 1, hh 0.1) turning at ``spin`` that dip below y = 0 within
    ``dt``, sampled finely (the box's own motion, no contact)."""
    t = np.linspace(0.0, dt, 2001)[:, None]
    theta = angle + spin * t
    lx, ly = np.array([1.0, -1.0, -1.0, 1.0]), 0.1 * np.array([1.0, 1.0, -1.0, -1.0])
    y = height + np.sin(theta) * lx + np.cos(theta) * ly
    return set(np.flatnonzero(y.min(axis=0) < 0.0).tolist())


def _box_plane_points(angle, height, spin) -> list[int]:
    """Feature ids of the box-plane points the engine's narrowphase stage makes for a box
    (hw 1, hh 0.1) above the ground, with its own margin (body terms, ``find_points``)."""
    world = p2.World(gravity=(0.0, 0.0))
    ground = world.add(p2.Plane())
    body = world.add(
        p2.Box(position=(0.0, height), width=2.0, height=0.2, angle=angle, angular_velocity=spin)
    )
    state, shapes = world.state, world.layout.shapes
    ctx = world.settings.step_context(DT)
    terms = np.zeros((state.body.shape[1], workspace.TERMS))
    integrate.step_terms(
        state.body,
        state.body_i,
        shapes,
        state.spring,
        world.layout.springs,
        state.hull,
        0,
        ctx,
        terms,
    )
    pairs = np.array([[body.slot, ground.slot]], np.int64)
    broadphase.pushed_reach(state.body, shapes, 0, ctx, terms, pairs, 0)  # no other body
    points = np.zeros((8, workspace.POINT_F))
    ids = np.zeros((8, 3), np.int64)
    n = narrowphase.find_points(
        state.body, state.hull, shapes, 0, ctx, terms, pairs, 1, points, ids
    )
    return ids[:n, 2].tolist()


@pytest.mark.parametrize(("spin", "count"), [(0.0, 1), (12.0, 3), (25.0, 4)])
def test_spinning_box_near_plane_gets_a_point_per_corner_in_reach(spin, count):
    """A long thin box tilted 0.1 rad, lowest corner 1 mm above the ground: at rest only
    that corner is in the margin; spinning at 12 and 25 rad/s the margin (what the box can
    close in a step) takes in 3 and 4 corners, ordered by id, among them every corner that
    would swing below the ground within the step."""
    angle = -0.1
    height = 0.001 + math.sin(0.1) * 1.0 + math.cos(0.1) * 0.1
    features = _box_plane_points(angle, height, spin)
    assert len(features) == count
    assert features == sorted(features)
    assert _corners_reaching_plane(angle, height, spin, DT) <= set(features)


# -- box against box ------------------------------------------------------------------------
def test_box_resting_on_bigger_box_normal_up_from_a():
    """A unit box resting on a 2 x 1 box: with A the lower box the normal is (0, 1), with A
    the upper one (0, -1); two points of separation 0 at the upper box's lower corners
    (1e-12), feature ids differing only in the incident vertex."""
    lower, upper = box(0, 0, 1.0, 0.5), box(0.2, 1.0, 0.5, 0.5)
    for a, b, normal in ((lower, upper, 1.0), (upper, lower, -1.0)):
        manifold = narrowphase.box_box(a, b, NO_ROW, NO_ROW, 0.02, 0.0)
        assert manifold[0] == 0b11
        np.testing.assert_allclose(normal_of(manifold), [0.0, normal], atol=1e-12)
        points = kept_points(manifold)
        corners = sorted(round(a[0] + p[0], 12) for p in points)
        assert corners == [-0.3, 0.7]
        assert all(abs(p[4]) < 1e-12 for p in points)
        assert points[0][5] // 4 == points[1][5] // 4 and points[0][5] < points[1][5]
        check_manifold(BOX_BOX, a, b, manifold)


def test_box_box_points_are_clipped_to_the_reference_face():
    """A 3 x 1 box resting on a unit box: the incident edge is clipped to the lower box's
    top face, so the points are at x = -0.5 and 0.5 (1e-12), separation 0."""
    a, b = box(0, 0, 0.5, 0.5), box(0, 1.0, 1.5, 0.5)
    manifold = narrowphase.box_box(a, b, NO_ROW, NO_ROW, 0.02, 0.0)
    points = kept_points(manifold)
    np.testing.assert_allclose(sorted(a[0] + p[0] for p in points), [-0.5, 0.5], atol=1e-12)
    np.testing.assert_allclose([p[4] for p in points], [0.0, 0.0], atol=1e-12)
    check_manifold(BOX_BOX, a, b, manifold)


@pytest.mark.parametrize("upper_half_width", [0.5, 1.5])
@pytest.mark.parametrize(
    ("dx", "dy", "dangle"),
    [(1e-4, 0, 0), (-1e-4, 1e-4, 0), (0, -1e-4, 1e-3), (0, 0, -1e-3), (1e-4, 1e-4, 1e-3)],
)
def test_box_box_features_survive_small_motion(dx, dy, dangle, upper_half_width):
    """Face to face boxes (the upper one narrower or wider than the lower): moving the top
    box by 1e-4 m or turning it by 1e-3 rad keeps the kept mask, the feature ids and the
    normal (1e-3) -- the reference face does not flip, which warm starting needs."""
    lower = box(0, 0, 1.0, 0.5)
    upper = box(0.2, 1.0, upper_half_width, 0.5)
    moved = box(0.2 + dx, 1.0 + dy, upper_half_width, 0.5, dangle)
    ref = narrowphase.box_box(lower, upper, NO_ROW, NO_ROW, 0.02, 0.0)
    after = narrowphase.box_box(lower, moved, NO_ROW, NO_ROW, 0.02, 0.0)
    assert after[0] == ref[0] == 0b11
    assert [p[5] for p in kept_points(after)] == [p[5] for p in kept_points(ref)]
    np.testing.assert_allclose(normal_of(after), normal_of(ref), atol=1e-3)


# -- circle against circle: the normal at the time of impact ----------------------------------
def test_circle_circle_normal_at_time_of_impact():
    """A at rest at the origin, B at (3r, r) moving (-v, 0): solving |d + u t| = 2r, they
    meet at d = (sqrt(3) r, r), so n = (sqrt(3)/2, 1/2) (1e-12), not the current line of
    centres (3, 1)/sqrt(10); the separation is n . d - 2r; rA and rB lie along n."""
    r, v = 0.5, 4.0
    a, b = circle(0, 0, r), circle(3 * r, r, r, v=(-v, 0.0))
    manifold = narrowphase.circle_circle(a, b, NO_ROW, NO_ROW, 1.0, 0.0)
    assert manifold[0] == 1
    n = normal_of(manifold)
    np.testing.assert_allclose(n, [math.sqrt(3) / 2, 0.5], atol=1e-12)
    assert math.degrees(math.acos(n @ np.array([3.0, 1.0]) / math.sqrt(10))) > 10.0
    rax, ray, rbx, rby, sep, _ = manifold[3]
    assert sep == pytest.approx(n @ [3 * r, r] - 2 * r, abs=1e-12)
    assert rax * n[1] - ray * n[0] == pytest.approx(0.0, abs=1e-12)
    assert rbx * n[1] - rby * n[0] == pytest.approx(0.0, abs=1e-12)
    # Along the normal the two anchors are the same point, midway between the surfaces.
    assert (np.array([a[0] + rax, a[1] + ray]) - [b[0] + rbx, b[1] + rby]) @ n == pytest.approx(
        0.0, abs=1e-12
    )
    check_manifold(CIRCLE_CIRCLE, a, b, manifold, same_point=False)


def test_circle_circle_miss_uses_closest_approach():
    """B passing above A, (3r, 3r) moving (-v, 0), never touches: the normal is the line of
    centres at closest approach, (0, 1), and the separation 3r - 2r = r (1e-12)."""
    r = 0.5
    manifold = narrowphase.circle_circle(
        circle(0, 0, r), circle(3 * r, 3 * r, r, (-4, 0)), NO_ROW, NO_ROW, 1.5, 0
    )
    np.testing.assert_allclose(normal_of(manifold), [0.0, 1.0], atol=1e-12)
    assert manifold[3][4] == pytest.approx(r, abs=1e-12)


def test_coincident_circles_normal_depends_on_tag():
    """Coincident centres: a unit normal picked by the tag, the same for the same tag,
    different (by > 1 degree) for each of 20 tags; separation -(ra + rb)."""
    a, b = circle(1.0, 2.0, 0.3), circle(1.0, 2.0, 0.2)
    normals = []
    for tag in range(20):
        manifold = narrowphase.circle_circle(a, b, NO_ROW, NO_ROW, 0.1, float(tag))
        again = narrowphase.circle_circle(a, b, NO_ROW, NO_ROW, 0.1, float(tag))
        assert manifold == again
        n = normal_of(manifold)
        assert np.linalg.norm(n) == pytest.approx(1.0, abs=1e-12)
        assert manifold[3][4] == pytest.approx(-0.5, abs=1e-12)
        check_manifold(CIRCLE_CIRCLE, a, b, manifold)
        normals.append(n)
    normals = np.array(normals)
    cosines = normals @ normals.T - 2.0 * np.eye(len(normals))
    assert cosines.max() < math.cos(math.radians(1.0))


# -- random shapes: the conventions hold everywhere --------------------------------------------
def _random_pair(kind, rng):
    kind_a, kind_b, _ = PAIRS[kind]

    def make(k, centre):
        if k == CIRCLE:
            return circle(*centre, rng.uniform(0.1, 0.8))
        if k == BOX:
            return box(*centre, *rng.uniform(0.1, 0.8, 2), rng.uniform(-np.pi, np.pi))
        angle = rng.uniform(-np.pi, np.pi)
        return plane(*centre, math.cos(angle), math.sin(angle))

    return make(kind_a, (0.0, 0.0)), make(kind_b, rng.uniform(-1.2, 1.2, 2))


@pytest.mark.parametrize("kind", TUTORIAL_PAIRS)
def test_random_shapes_obey_the_conventions(kind):
    """200 random placements per pair (at rest, overlapping or not): every manifold has a
    unit normal, A + rA = B + rB, and the point lies midway: P -/+ (s/2) n on A's/B's surface
    (1e-12); points come out ordered by feature id."""
    rng = np.random.default_rng(kind)
    found = 0
    for _ in range(200):
        a, b = _random_pair(kind, rng)
        manifold = PAIRS[kind][2](a, b, NO_ROW, NO_ROW, 0.3, float(rng.integers(100)))
        if manifold[0]:
            found += 1
            check_manifold(kind, a, b, manifold)
            features = [p[5] for p in kept_points(manifold)]
            assert features == sorted(features)
    assert found > 50


@pytest.mark.parametrize("seed", range(3))
def test_circle_box_separation_is_signed_distance(seed):
    """Disc against box at 300 random placements, inside and out: the separation is the
    signed distance from the disc's centre to the box minus the radius (1e-12)."""
    rng = np.random.default_rng(seed)
    for _ in range(300):
        a, b = _random_pair(CIRCLE_BOX, rng)
        manifold = narrowphase.circle_box(a, b, NO_ROW, NO_ROW, 10.0, 0.0)
        expected = distance(b, BOX, (a[0], a[1])) - a[4]
        assert manifold[3][4] == pytest.approx(expected, abs=1e-12)


# -- the registry and the dispatch ------------------------------------------------------------
@pytest.mark.parametrize("kind", TUTORIAL_PAIRS)
def test_collide_dispatches_as_the_registry_says(kind):
    """``collide(k, ...)`` returns exactly ``PAIRS[k][2](...)`` for every pair kind, on 50
    random placements each."""
    rng = np.random.default_rng(100 + kind)
    function = PAIRS[kind][2]
    for _ in range(50):
        a, b = _random_pair(kind, rng)
        assert narrowphase.collide(kind, a, b, NO_ROW, NO_ROW, 0.3, 5.0) == function(
            a, b, NO_ROW, NO_ROW, 0.3, 5.0
        )


def test_pair_kind_matches_the_registry():
    """``pair_kind(kind_a, kind_b)`` is the registry key for each entry's kinds; every
    ordered pair of shape kinds but plane-plane has exactly one entry."""
    for key, (kind_a, kind_b, _) in PAIRS.items():
        assert narrowphase.pair_kind(kind_a, kind_b) == key
    kinds = (CIRCLE, BOX, POLYGON, PLANE)
    ordered = [(a, b) for a in kinds for b in kinds if a <= b]
    registered = sorted((kind_a, kind_b) for kind_a, kind_b, _ in PAIRS.values())
    assert registered == sorted(set(ordered) - {(PLANE, PLANE)})
    assert narrowphase.pair_kind(PLANE, PLANE) == -1
