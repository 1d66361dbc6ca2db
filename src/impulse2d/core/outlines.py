"""Narrowphase of outlines: convex polygons (capsules and segments among them) against
circles, boxes, polygons and planes. ``narrowphase.PAIRS`` registers these beside the
tutorial's pairs and follows their conventions (its docstring): the normal from A to B,
anchors from each centre, a point midway between the surfaces, points ordered by
feature id, kept within the margin (speculative contacts).

An *outline* is a row of ``state.hull`` (``HULL_F`` numbers, body frame, origin at the
centre of mass): ``VERTEX_COUNT`` vertices counter-clockwise, each edge's outward unit
normal, and a rounding radius; the shape is every point within the radius of the convex
polygon. A capsule is an outline of two vertices (its two "edges" run there and back,
with opposite normals) and a segment one of radius 0. A box taking part in a polygon
pair is read as the outline of its four corners, numbered as ``box_plane`` numbers them
(counter-clockwise from (+, +)), from an empty row: ``_vertex`` and ``_normal`` build
them from its half sizes.

The polygon pair is Box2D v3's method in outline (``manifold.c``, read, not copied):
separating axes over both shapes' edge normals pick a reference edge and an incident
one; when the cores are apart by more than a sliver and their closest features are two
vertices, one point on the line between them (so a rounded corner, or a corner passing
a corner, is not stopped by an edge's extension); otherwise the incident edge clipped to
the reference edge's extent, up to two points.
"""

from __future__ import annotations

import math

from ._jit import kernel
from .state import EDGE_NORMAL0, ROUNDING, VERTEX0, VERTEX_COUNT

# A shape tuple's fields (narrowphase.shape): centre, rotation, half sizes, normal.
_SX, _SY, _SCOS, _SSIN, _SHW, _SHH, _SNX, _SNY = 0, 1, 2, 3, 4, 5, 8, 9
NO_POINT = (0.0, 0.0, 0.0, 0.0, 0.0, 0)
# The reference edge is B's only if B's axis separates by this much more than A's (m):
# a tenth of the linear slop, as Box2D; without it the reference flips between frames
# for shapes resting flat, and warm starting loses its impulses.
_FLIP_TOLERANCE = 0.0005
# Cores apart by more than this (m) may meet vertex to vertex (see the module docstring).
_APART = 0.0005
# Feature ids: 8 * reference edge + incident vertex, plus _B_REFERENCE when the reference
# edge is B's (narrowphase.anchor_kept: then A's vertex is the material point).
B_REFERENCE = 64


@kernel
def _count(row) -> int:
    return 4 if row.shape[0] == 0 else int(row[VERTEX_COUNT])


@kernel
def _radius(row) -> float:
    return 0.0 if row.shape[0] == 0 else row[ROUNDING]


@kernel
def _vertex(shape, row, k):
    """Vertex ``k`` in the body frame: the outline's, or a box's corner."""
    if row.shape[0] == 0:
        x = shape[_SHW] if k == 0 or k == 3 else -shape[_SHW]
        y = shape[_SHH] if k < 2 else -shape[_SHH]
        return x, y
    return row[VERTEX0 + 2 * k], row[VERTEX0 + 2 * k + 1]


@kernel
def _normal(row, k):
    """The outward unit normal of edge ``k`` (vertex ``k`` to ``k + 1``), body frame."""
    if row.shape[0] == 0:
        if k == 0:
            return 0.0, 1.0
        if k == 1:
            return -1.0, 0.0
        return (0.0, -1.0) if k == 2 else (1.0, 0.0)
    return row[EDGE_NORMAL0 + 2 * k], row[EDGE_NORMAL0 + 2 * k + 1]


@kernel
def _relative(one, other):
    """``other``'s pose in ``one``'s frame: its origin and rotation (cos, sin)."""
    c, s = one[_SCOS], one[_SSIN]
    dx, dy = other[_SX] - one[_SX], other[_SY] - one[_SY]
    oc, os_ = other[_SCOS], other[_SSIN]
    return c * dx + s * dy, -s * dx + c * dy, c * oc + s * os_, c * os_ - s * oc


@kernel
def _max_separation(one, row_one, other, row_other):
    """The edge of ``one`` whose normal separates ``other`` most, and by how much (m,
    cores only: the radii are not subtracted): ``max_k min_j n_k . (v_j - v_k)``."""
    tx, ty, rc, rs = _relative(one, other)
    best, edge = -math.inf, 0
    for k in range(_count(row_one)):
        nx, ny = _normal(row_one, k)
        vx, vy = _vertex(one, row_one, k)
        least = math.inf
        for j in range(_count(row_other)):
            ux, uy = _vertex(other, row_other, j)
            px, py = tx + rc * ux - rs * uy, ty + rs * ux + rc * uy
            least = min(least, nx * (px - vx) + ny * (py - vy))
        if least > best:
            best, edge = least, k
    return edge, best


@kernel
def _closest_on_segments(p1x, p1y, q1x, q1y, p2x, p2y, q2x, q2y):
    """Fractions ``(s, t)`` along segments ``p1 q1`` and ``p2 q2`` of their closest points.

    Minimise ``|p1 + s d1 - p2 - t d2|^2`` over the unit square: for a fixed ``s`` the
    best ``t`` is ``(b s + f) / e`` clamped (``b = d1.d2``, ``e = d2.d2``, ``f =
    d2.(p1 - p2)``), and ``s`` solves the 2x2 normal equations, clamped, then ``t``
    again, then ``s`` again for a clamped ``t``."""
    d1x, d1y, d2x, d2y = q1x - p1x, q1y - p1y, q2x - p2x, q2y - p2y
    rx, ry = p1x - p2x, p1y - p2y
    a, e = d1x * d1x + d1y * d1y, d2x * d2x + d2y * d2y
    b, c, f = d1x * d2x + d1y * d2y, d1x * rx + d1y * ry, d2x * rx + d2y * ry
    denominator = a * e - b * b
    s = min(max((b * f - c * e) / denominator, 0.0), 1.0) if denominator > 0.0 else 0.0
    t = (b * s + f) / e
    if t < 0.0:
        t, s = 0.0, min(max(-c / a, 0.0), 1.0)
    elif t > 1.0:
        t, s = 1.0, min(max((b - c) / a, 0.0), 1.0)
    return s, t


@kernel
def _to_world(shape, x, y):
    """A point of ``shape``'s frame in world coordinates."""
    c, s = shape[_SCOS], shape[_SSIN]
    return shape[_SX] + c * x - s * y, shape[_SY] + s * x + c * y


@kernel
def _point(a, b, ref, x, y, normal_x, normal_y, separation, feature):
    """A manifold point from a midway point ``(x, y)`` in ``ref``'s frame."""
    wx, wy = _to_world(ref, x, y)
    return wx - a[_SX], wy - a[_SY], wx - b[_SX], wy - b[_SY], separation, feature


@kernel
def polygon_polygon(a, b, row_a, row_b, margin, tag):
    """Two outlines (either may be a box: an empty row), up to two points (the module
    docstring). Feature ids: ``8 * reference edge + incident vertex``, plus ``B_REFERENCE``
    when the reference edge is B's."""
    edge_a, gap_a = _max_separation(a, row_a, b, row_b)
    edge_b, gap_b = _max_separation(b, row_b, a, row_a)
    radius_ref, radius_inc = _radius(row_a), _radius(row_b)
    flip = gap_b > gap_a + _FLIP_TOLERANCE
    gap = gap_b if flip else gap_a
    if gap - radius_ref - radius_inc >= margin:
        return 0, 0.0, 0.0, NO_POINT, NO_POINT, NO_POINT, NO_POINT
    ref, inc, row_ref, row_inc, i1 = (
        (b, a, row_b, row_a, edge_b) if flip else (a, b, row_a, row_b, edge_a)
    )
    if flip:
        radius_ref, radius_inc = radius_inc, radius_ref
    n_ref, n_inc = _count(row_ref), _count(row_inc)
    i2 = i1 + 1 if i1 + 1 < n_ref else 0
    nx, ny = _normal(row_ref, i1)
    tx, ty, rc, rs = _relative(ref, inc)
    j1, least = 0, math.inf  # the incident edge: its normal most opposed to the reference's
    for j in range(n_inc):
        mx, my = _normal(row_inc, j)
        along = nx * (rc * mx - rs * my) + ny * (rs * mx + rc * my)
        if along < least:
            j1, least = j, along
    j2 = j1 + 1 if j1 + 1 < n_inc else 0
    v11x, v11y = _vertex(ref, row_ref, i1)
    v12x, v12y = _vertex(ref, row_ref, i2)
    ux, uy = _vertex(inc, row_inc, j1)
    v21x, v21y = tx + rc * ux - rs * uy, ty + rs * ux + rc * uy
    ux, uy = _vertex(inc, row_inc, j2)
    v22x, v22y = tx + rc * ux - rs * uy, ty + rs * ux + rc * uy
    base = B_REFERENCE if flip else 0
    if gap > _APART:
        s, t = _closest_on_segments(v11x, v11y, v12x, v12y, v21x, v21y, v22x, v22y)
        if (s == 0.0 or s == 1.0) and (t == 0.0 or t == 1.0):
            feature = base + 8 * (i1 if s == 0.0 else i2) + (j1 if t == 0.0 else j2)
            return _vertex_vertex(
                a, b, ref, flip, v11x, v11y, v12x, v12y, v21x, v21y, v22x, v22y, s, t,
                radius_ref, radius_inc, margin, feature,
            )  # fmt: skip
    return _clip(
        a, b, ref, flip, v11x, v11y, v12x, v12y, v21x, v21y, v22x, v22y, nx, ny, radius_ref,
        radius_inc, margin, base + 8 * i1 + j1, base + 8 * i1 + j2,
    )  # fmt: skip


@kernel
def _vertex_vertex(a, b, ref, flip, v11x, v11y, v12x, v12y, v21x, v21y, v22x, v22y, s, t,
                   radius_ref, radius_inc, margin, feature):  # fmt: skip
    """One point on the line between the two closest vertices (``ref``'s frame)."""
    px, py = v11x + s * (v12x - v11x), v11y + s * (v12y - v11y)
    qx, qy = v21x + t * (v22x - v21x), v21y + t * (v22y - v21y)
    dx, dy = qx - px, qy - py
    distance = math.sqrt(dx * dx + dy * dy)
    separation = distance - radius_ref - radius_inc
    if separation >= margin or distance == 0.0:
        return 0, 0.0, 0.0, NO_POINT, NO_POINT, NO_POINT, NO_POINT
    nx, ny = dx / distance, dy / distance
    reach = radius_ref + 0.5 * separation  # from the reference vertex to the midpoint
    point = _point(a, b, ref, px + reach * nx, py + reach * ny, nx, ny, separation, feature)
    wnx, wny = ref[_SCOS] * nx - ref[_SSIN] * ny, ref[_SSIN] * nx + ref[_SCOS] * ny
    if flip:
        wnx, wny = -wnx, -wny
    return 1, wnx, wny, point, NO_POINT, NO_POINT, NO_POINT


@kernel
def _clip(a, b, ref, flip, v11x, v11y, v12x, v12y, v21x, v21y, v22x, v22y, nx, ny,
          radius_ref, radius_inc, margin, f1, f2):  # fmt: skip
    """The incident edge ``v21 v22`` clipped to the reference edge ``v11 v12``'s extent
    (``ref``'s frame), each end's separation along the reference normal ``n``."""
    ex, ey = v12x - v11x, v12y - v11y
    length = math.sqrt(ex * ex + ey * ey)
    tx, ty = ex / length, ey / length
    u1 = (v21x - v11x) * tx + (v21y - v11y) * ty
    u2 = (v22x - v11x) * tx + (v22y - v11y) * ty
    if (u1 > length and u2 > length) or (u1 < 0.0 and u2 < 0.0):
        return 0, 0.0, 0.0, NO_POINT, NO_POINT, NO_POINT, NO_POINT
    span = 1.0 if u2 == u1 else u2 - u1
    lam1 = (min(max(u1, 0.0), length) - u1) / span  # fraction from v21 towards v22
    lam2 = (min(max(u2, 0.0), length) - u2) / -span  # fraction from v22 towards v21
    p1x, p1y = v21x + lam1 * (v22x - v21x), v21y + lam1 * (v22y - v21y)
    p2x, p2y = v22x + lam2 * (v21x - v22x), v22y + lam2 * (v21y - v22y)
    if f1 > f2:  # points ordered by feature id (the incident edge's end wrapped to 0)
        p1x, p1y, p2x, p2y, f1, f2 = p2x, p2y, p1x, p1y, f2, f1
    radius = radius_ref + radius_inc
    gap1 = (p1x - v11x) * nx + (p1y - v11y) * ny
    gap2 = (p2x - v11x) * nx + (p2y - v11y) * ny
    # Midway between the incident surface (p - r_inc n) and the reference's (p - gap n
    # + r_ref n): p + (r_ref - r_inc - gap) n / 2.
    shift1, shift2 = 0.5 * (radius_ref - radius_inc - gap1), 0.5 * (radius_ref - radius_inc - gap2)
    first = _point(a, b, ref, p1x + shift1 * nx, p1y + shift1 * ny, nx, ny, gap1 - radius, f1)
    second = _point(a, b, ref, p2x + shift2 * nx, p2y + shift2 * ny, nx, ny, gap2 - radius, f2)
    kept = (1 if gap1 - radius < margin else 0) | (2 if gap2 - radius < margin else 0)
    wnx, wny = ref[_SCOS] * nx - ref[_SSIN] * ny, ref[_SSIN] * nx + ref[_SCOS] * ny
    if flip:
        wnx, wny = -wnx, -wny
    return kept, wnx, wny, first, second, NO_POINT, NO_POINT


@kernel
def circle_polygon(a, b, row_a, row_b, margin, tag):
    """Disc A against outline B: the edge that separates the centre most, or, where the
    centre lies beyond one of that edge's ends (outside the outline), that vertex."""
    c, s = b[_SCOS], b[_SSIN]
    dx, dy = a[_SX] - b[_SX], a[_SY] - b[_SY]
    px, py = c * dx + s * dy, -s * dx + c * dy  # the centre in B's frame
    radius = a[_SHW] + _radius(row_b)
    n = _count(row_b)
    best, edge = -math.inf, 0
    for k in range(n):
        nx, ny = _normal(row_b, k)
        vx, vy = _vertex(b, row_b, k)
        gap = nx * (px - vx) + ny * (py - vy)
        if gap > best:
            best, edge = gap, k
    if best - radius >= margin:
        return 0, 0.0, 0.0, NO_POINT, NO_POINT, NO_POINT, NO_POINT
    v1x, v1y = _vertex(b, row_b, edge)
    v2x, v2y = _vertex(b, row_b, edge + 1 if edge + 1 < n else 0)
    nx, ny = _normal(row_b, edge)
    core = best  # the centre's distance from B's core along n
    before = (px - v1x) * (v2x - v1x) + (py - v1y) * (v2y - v1y) < 0.0
    after = (px - v2x) * (v1x - v2x) + (py - v2y) * (v1y - v2y) < 0.0
    if best > 0.0 and (before or after):
        qx, qy = (v1x, v1y) if before else (v2x, v2y)
        ox, oy = px - qx, py - qy
        core = math.sqrt(ox * ox + oy * oy)
        nx, ny = ox / core, oy / core
    separation = core - radius
    if separation >= margin:
        return 0, 0.0, 0.0, NO_POINT, NO_POINT, NO_POINT, NO_POINT
    # Midway between the disc's surface (centre - r_a n) and B's (centre - (core - r_b) n).
    back = a[_SHW] + 0.5 * separation
    wx, wy = _to_world(b, px - back * nx, py - back * ny)
    wnx, wny = -(c * nx - s * ny), -(s * nx + c * ny)  # A -> B: disc towards the outline
    point = (wx - a[_SX], wy - a[_SY], wx - b[_SX], wy - b[_SY], separation, 0)
    return 1, wnx, wny, point, NO_POINT, NO_POINT, NO_POINT


@kernel
def _plane_gap(a, row_a, b, k):
    """Vertex ``k`` of outline A against plane B: its separation (radius subtracted) and
    its point midway between the surfaces, in world coordinates."""
    lx, ly = _vertex(a, row_a, k)
    wx, wy = _to_world(a, lx, ly)
    nx, ny = b[_SNX], b[_SNY]
    radius = _radius(row_a)
    separation = (wx - b[_SX]) * nx + (wy - b[_SY]) * ny - radius
    reach = radius + 0.5 * separation
    return separation, wx - reach * nx, wy - reach * ny


@kernel
def _plane_point(a, row_a, b, k):
    separation, wx, wy = _plane_gap(a, row_a, b, k)
    return wx - a[_SX], wy - a[_SY], wx - b[_SX], wy - b[_SY], separation, k


@kernel
def _nth_vertex(mask, nth) -> int:
    """The index of the ``nth`` set bit of ``mask`` (-1: fewer bits set)."""
    seen = 0
    for k in range(8):
        if mask & (1 << k):
            if seen == nth:
                return k
            seen += 1
    return -1


@kernel
def polygon_plane(a, b, row_a, row_b, margin, tag):
    """Outline A against half-space B: the deepest of its vertices within the margin, at
    most four (a box keeps all its corners, as ``box_plane``: a spinning shape's corner
    about to swing down must be a speculative contact). Feature id: the vertex."""
    chosen = 0
    for _ in range(4):
        pick, least = -1, margin
        for k in range(_count(row_a)):
            if chosen & (1 << k) == 0:
                gap = _plane_gap(a, row_a, b, k)[0]
                if gap < least:
                    pick, least = k, gap
        if pick < 0:
            break
        chosen |= 1 << pick
    k0, k1 = _nth_vertex(chosen, 0), _nth_vertex(chosen, 1)
    k2, k3 = _nth_vertex(chosen, 2), _nth_vertex(chosen, 3)
    p0 = _plane_point(a, row_a, b, k0) if k0 >= 0 else NO_POINT
    p1 = _plane_point(a, row_a, b, k1) if k1 >= 0 else NO_POINT
    p2 = _plane_point(a, row_a, b, k2) if k2 >= 0 else NO_POINT
    p3 = _plane_point(a, row_a, b, k3) if k3 >= 0 else NO_POINT
    kept = (1 if k0 >= 0 else 0) | (2 if k1 >= 0 else 0) | (4 if k2 >= 0 else 0)
    kept |= 8 if k3 >= 0 else 0
    return kept, -b[_SNX], -b[_SNY], p0, p1, p2, p3
