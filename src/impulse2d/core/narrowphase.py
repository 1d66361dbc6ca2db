"""Narrowphase: the contact points of one pair, one function per pair of shape kinds.

Conventions, used throughout the engine:

* A pair ``(A, B)`` always has ``kind(A) <= kind(B)`` (circle < box < polygon < plane),
  so nine functions cover every pair; plane-plane never collides. ``PAIRS`` is the one
  registry of them, and ``collide`` dispatches by it. The polygon pairs (capsules and
  segments are polygons) live in ``outlines.py``.
* The normal ``n`` points from A to B. The separation is the signed gap along it,
  negative when the shapes overlap.
* A point's anchors ``rA``, ``rB`` are its offsets from A's and B's centres, in world
  orientation. The point is midway between the two surfaces.
* A point is kept when ``separation < margin``: the margin is the *speculative* distance
  of the pair (how far the two can close during this step), so a fast body gets its
  contact before it reaches the surface and cannot tunnel.
* Points of a pair come out ordered by feature id (which vertex of which face made
  them), which lets the solver carry their impulses over to the next step. A pair has
  up to two points, except a box or polygon against a plane: a speculative point at
  each corner (at most four).

Each function is pure: it takes the two shapes as tuples of numbers (``shape``), their
outlines (a polygon's row of ``state.hull``; an empty row for every other shape, which
only the polygon pairs read) and the margin, and returns a *manifold*:
``(kept, nx, ny, p0, p1, p2, p3)``, the unit normal and up to four points
``(rax, ray, rbx, rby, separation, feature)``, bit ``k`` of ``kept`` saying that point
``k`` is in it. (Plain numbers and rows in and out cost nothing to pass in compiled code
and are easy to test on hand-built shapes.)
"""

from __future__ import annotations

import math

from . import context
from ._jit import kernel
from .outlines import B_REFERENCE, circle_polygon, polygon_plane, polygon_polygon
from .state import (
    BOX,
    CIRCLE,
    COS,
    HALF_H,
    HALF_W,
    NORMAL_X,
    NORMAL_Y,
    PLANE,
    POLYGON,
    SIN,
    VX,
    VY,
    X,
    Y,
)
from .workspace import (
    AGAINST_PLANE,
    HALF_SPEC,
    KEEP,
    NX,
    NY,
    PUSHED,
    RAX,
    RAY,
    RBX,
    RBY,
    REACH,
    SEP0,
)

CIRCLE_CIRCLE, CIRCLE_BOX, BOX_BOX, CIRCLE_PLANE, BOX_PLANE = range(5)
CIRCLE_POLYGON, BOX_POLYGON, POLYGON_POLYGON, POLYGON_PLANE = range(5, 9)
# Feature ids are < 128 (polygons: 2 reference sides x 8 edges x 8 incident vertices).
FEATURES = 2 * B_REFERENCE
_GOLDEN_ANGLE = math.pi * (3.0 - math.sqrt(5.0))
# A shape: (x, y, cos, sin, half_w, half_h, vx, vy, normal_x, normal_y). A circle's radius is
# its half width; a plane's point is (x, y).
SX, SY, SCOS, SSIN, SHW, SHH, SVX, SVY, SNX, SNY = range(10)
NO_POINT = (0.0, 0.0, 0.0, 0.0, 0.0, 0)


@kernel
def shape(x, y, cos, sin, half_w, half_h, vx, vy, normal_x, normal_y):
    """A shape as the pair functions take it (see the module docstring)."""
    return (
        float(x), float(y), float(cos), float(sin), float(half_w), float(half_h),
        float(vx), float(vy), float(normal_x), float(normal_y),
    )  # fmt: skip


@kernel
def shape_of(body, terms, w, i):
    """Body ``i`` of world ``w`` as a shape."""
    return (
        body[w, i, X], body[w, i, Y], body[w, i, COS], body[w, i, SIN], body[w, i, HALF_W],
        body[w, i, HALF_H], body[w, i, VX], body[w, i, VY], body[w, i, NORMAL_X],
        body[w, i, NORMAL_Y],
    )  # fmt: skip


@kernel
def circle_circle(a, b, row_a, row_b, margin, tag):
    """Two discs: one point, on the line of centres *where they will meet*.

    A speculative contact constrains motion along one normal: ``n . (relative motion) >=
    -separation``, a half-plane touching the disc of forbidden offsets. Taking ``n`` from
    the positions at the start of the step is right for discs that close head on, but for
    two balls approaching at an angle it is not the line of centres when they touch, and
    the struck ball leaves a few degrees off (3 degrees at 4 m/s and 60 Hz). Discs move
    in straight lines within a step, so the normal is taken at the time of impact ``t``
    solving ``|d + u t| = R`` (``d`` the offset of the centres, ``u`` their relative
    velocity, ``R`` the sum of radii) if they will meet, else at the time of closest
    approach; the separation is then ``n . d - R``. Coincident centres have no line of
    centres: ``tag`` (a number per pair) picks a direction by the golden angle,
    deterministic and different for every pair, so a pile spawned in one spot fans out.
    """
    ra, rb = a[SHW], b[SHW]
    dx, dy = b[SX] - a[SX], b[SY] - a[SY]
    dist = math.sqrt(dx * dx + dy * dy)
    reach = ra + rb
    separation = dist - reach
    if separation >= margin:
        return 0, 0.0, 0.0, NO_POINT, NO_POINT, NO_POINT, NO_POINT
    ux, uy = b[SVX] - a[SVX], b[SVY] - a[SVY]
    closing = dx * ux + dy * uy  # d . u < 0: approaching
    speed2 = ux * ux + uy * uy  # 0 for speeds so small their square underflows
    ahead = separation > 0.0 and closing < 0.0 and speed2 > 0.0
    tx, ty, length = dx, dy, dist
    if ahead:
        # Impact: u.u t^2 + 2 d.u t + (d.d - R^2) = 0, the first root; a miss: t = -d.u / u.u.
        disc = closing * closing - speed2 * (dist * dist - reach * reach)
        when = (-closing - math.sqrt(disc)) / speed2 if disc >= 0.0 else -closing / speed2
        tx, ty = dx + ux * when, dy + uy * when
        length = math.sqrt(tx * tx + ty * ty)
    if length < 1e-12:
        phi = tag * _GOLDEN_ANGLE
        nx, ny = math.cos(phi), math.sin(phi)
    else:
        nx, ny = tx / length, ty / length
    if ahead:
        separation = nx * dx + ny * dy - reach
    # Anchors on the normal through each centre, so the normal impulse never turns a disc.
    reach_a, reach_b = ra + 0.5 * separation, -(rb + 0.5 * separation)
    point = (nx * reach_a, ny * reach_a, nx * reach_b, ny * reach_b, separation, 0)
    return 1, nx, ny, point, NO_POINT, NO_POINT, NO_POINT


@kernel
def circle_box(a, b, row_a, row_b, margin, tag):
    """Disc A against box B: the closest point on the box, or the nearest face if inside."""
    c, s = b[SCOS], b[SSIN]
    hw, hh, r = b[SHW], b[SHH], a[SHW]
    dx, dy = a[SX] - b[SX], a[SY] - b[SY]  # circle from the box
    px, py = c * dx + s * dy, -s * dx + c * dy  # ... in the box's frame
    qx, qy = min(max(px, -hw), hw), min(max(py, -hh), hh)
    ox, oy = px - qx, py - qy
    dist = math.sqrt(ox * ox + oy * oy)
    if dist > 0.0:  # outside: towards the closest point
        lnx, lny, sx, sy = ox / dist, oy / dist, qx, qy
        separation = dist - r
    else:  # inside: out through the face of least penetration
        depth_x, depth_y = hw - abs(px), hh - abs(py)
        signx = 1.0 if px >= 0.0 else -1.0
        signy = 1.0 if py >= 0.0 else -1.0
        if depth_x <= depth_y:
            lnx, lny, sx, sy, separation = signx, 0.0, signx * hw, py, -depth_x - r
        else:
            lnx, lny, sx, sy, separation = 0.0, signy, px, signy * hh, -depth_y - r
    if separation >= margin:
        return 0, 0.0, 0.0, NO_POINT, NO_POINT, NO_POINT, NO_POINT
    nx, ny = -(c * lnx - s * lny), -(s * lnx + c * lny)  # A -> B: circle towards box
    box_x, box_y = c * sx - s * sy, s * sx + c * sy  # surface point from the box centre
    # Midway between the box surface point and the circle's (A + r n), from A.
    rax, ray = 0.5 * (box_x - dx + r * nx), 0.5 * (box_y - dy + r * ny)
    point = (rax, ray, rax + dx, ray + dy, separation, 0)
    return 1, nx, ny, point, NO_POINT, NO_POINT, NO_POINT


@kernel
def circle_plane(a, b, row_a, row_b, margin, tag):
    """Disc A against half-space B: one point below the centre."""
    nx, ny, r = b[SNX], b[SNY], a[SHW]
    ox, oy = a[SX] - b[SX], a[SY] - b[SY]
    separation = ox * nx + oy * ny - r
    if separation >= margin:
        return 0, 0.0, 0.0, NO_POINT, NO_POINT, NO_POINT, NO_POINT
    reach = r + 0.5 * separation
    rax, ray = -nx * reach, -ny * reach
    point = (rax, ray, rax + ox, ray + oy, separation, 0)
    return 1, -nx, -ny, point, NO_POINT, NO_POINT, NO_POINT


@kernel
def _corner(a, b, corner, base, margin):
    """Corner ``corner`` of box A against plane B, and whether it is within the margin."""
    c, s, nx, ny = a[SCOS], a[SSIN], b[SNX], b[SNY]
    lx = a[SHW] * (1.0 if corner == 0 or corner == 3 else -1.0)
    ly = a[SHH] * (1.0 if corner < 2 else -1.0)
    rx, ry = c * lx - s * ly, s * lx + c * ly
    separation = base + rx * nx + ry * ny
    px, py = rx - 0.5 * separation * nx, ry - 0.5 * separation * ny
    ox, oy = a[SX] - b[SX], a[SY] - b[SY]
    return separation < margin, (px, py, px + ox, py + oy, separation, corner)


@kernel
def box_plane(a, b, row_a, row_b, margin, tag):
    """Box A against half-space B: every corner within the margin (up to four).

    A resting box has two (its lower corners); a box spinning fast near the ground can
    have three or four, and each must be a speculative contact or the corner about to
    swing down would pass through the ground within the step. A corner's feature id is
    its index, counter-clockwise from (+, +).
    """
    base = (a[SX] - b[SX]) * b[SNX] + (a[SY] - b[SY]) * b[SNY]
    k0, p0 = _corner(a, b, 0, base, margin)
    k1, p1 = _corner(a, b, 1, base, margin)
    k2, p2 = _corner(a, b, 2, base, margin)
    k3, p3 = _corner(a, b, 3, base, margin)
    kept = (1 if k0 else 0) | (2 if k1 else 0) | (4 if k2 else 0) | (8 if k3 else 0)
    return kept, -b[SNX], -b[SNY], p0, p1, p2, p3


@kernel
def _pick(axis, v0, v1, v2, v3) -> float:
    if axis == 0:
        return v0
    if axis == 1:
        return v1
    return v2 if axis == 2 else v3


@kernel
def _reference_axis(a, b):
    """Separating axes: the face axis of least penetration (or greatest separation) among
    A's two and B's two, and its separation. A's axes are preferred unless B's are clearly
    better (5 % relative, 1 % of the box size absolute): without that preference the
    reference face flips between frames for boxes resting flat, and warm starting loses
    its impulses."""
    ca, sa, cb, sb = a[SCOS], a[SSIN], b[SCOS], b[SSIN]
    hwa, hha, hwb, hhb = a[SHW], a[SHH], b[SHW], b[SHH]
    dx, dy = b[SX] - a[SX], b[SY] - a[SY]
    dax, day = dx * ca + dy * sa, -dx * sa + dy * ca  # B's centre in A's frame
    dbx, dby = dx * cb + dy * sb, -dx * sb + dy * cb  # ... projected on B's axes
    # |R_A^T R_B|: the rotation between the boxes has entries (c00, c01; -c01, c00).
    a00, a01 = abs(ca * cb + sa * sb), abs(sa * cb - ca * sb)
    g0 = abs(dax) - hwa - (hwb * a00 + hhb * a01)
    g1 = abs(day) - hha - (hwb * a01 + hhb * a00)
    g2 = abs(dbx) - hwb - (hwa * a00 + hha * a01)
    g3 = abs(dby) - hhb - (hwa * a01 + hha * a00)
    axis, best = 0, g0
    for index in range(1, 4):
        gap = _pick(index, g0, g1, g2, g3)
        if gap > best + 0.05 * abs(best) + 0.01 * _pick(index, hwa, hha, hwb, hhb):
            axis, best = index, gap
    sign = 1.0 if _pick(axis, dax, day, dbx, dby) >= 0.0 else -1.0
    return axis, best, sign


@kernel
def _incident_edge(inc, ref_x, ref_y):
    """The edge of box ``inc`` whose face is most opposed to the reference normal: its two
    vertices in the box's frame."""
    ic, is_ = inc[SCOS], inc[SSIN]
    ihw, ihh = inc[SHW], inc[SHH]
    along_x = ref_x * ic + ref_y * is_  # n_ref . (incident box x axis)
    along_y = -ref_x * is_ + ref_y * ic
    x_face = abs(along_x) >= abs(along_y)
    face_sign = -1.0 if (along_x if x_face else along_y) >= 0.0 else 1.0
    l1x, l1y = (face_sign * ihw, ihh) if x_face else (ihw, face_sign * ihh)
    l2x, l2y = (face_sign * ihw, -ihh) if x_face else (-ihw, face_sign * ihh)
    return l1x, l1y, l2x, l2y


@kernel
def box_box(a, b, row_a, row_b, margin, tag):
    """Two boxes by separating axes, with up to two points clipped from the incident edge.

    The axis of ``_reference_axis`` picks a *reference* face; the face of the other box
    most opposed to it is the *incident* face, whose edge is clipped to the reference
    face's extent (Sutherland-Hodgman against its two side planes). Feature ids:
    reference face (axis and side: 8) x incident vertex (4, counter-clockwise from (+, +)).
    """
    axis, best, sign = _reference_axis(a, b)
    if best >= margin:
        return 0, 0.0, 0.0, NO_POINT, NO_POINT, NO_POINT, NO_POINT
    ref_is_b = axis >= 2
    ref, inc = (b, a) if ref_is_b else (a, b)
    flip = -sign if ref_is_b else sign  # B's faces point from B towards A
    rc, rs = ref[SCOS], ref[SSIN]
    ref_x = flip * (rc if axis % 2 == 0 else -rs)
    ref_y = flip * (rs if axis % 2 == 0 else rc)
    offset = ref[SHW] if axis % 2 == 0 else ref[SHH]
    side = ref[SHH] if axis % 2 == 0 else ref[SHW]
    centre_x, centre_y = ref[SX] + offset * ref_x, ref[SY] + offset * ref_y  # face centre
    l1x, l1y, l2x, l2y = _incident_edge(inc, ref_x, ref_y)
    ic, is_ = inc[SCOS], inc[SSIN]
    v1x, v1y = inc[SX] + ic * l1x - is_ * l1y, inc[SY] + is_ * l1x + ic * l1y
    v2x, v2y = inc[SX] + ic * l2x - is_ * l2y, inc[SY] + is_ * l2x + ic * l2y
    u1 = (v1x - centre_x) * -ref_y + (v1y - centre_y) * ref_x  # along the face (tangent)
    u2 = (v2x - centre_x) * -ref_y + (v2y - centre_y) * ref_x
    if (u1 > side and u2 > side) or (u1 < -side and u2 < -side):
        return 0, 0.0, 0.0, NO_POINT, NO_POINT, NO_POINT, NO_POINT
    span = 1.0 if u2 == u1 else u2 - u1
    lam1 = (min(max(u1, -side), side) - u1) / span  # fraction from v1 towards v2
    lam2 = (min(max(u2, -side), side) - u2) / -span  # fraction from v2 towards v1
    p1x, p1y = v1x + lam1 * (v2x - v1x), v1y + lam1 * (v2y - v1y)
    p2x, p2y = v2x + lam2 * (v1x - v2x), v2y + lam2 * (v1y - v2y)
    face = 2 * axis + (1 if sign < 0.0 else 0)
    f1 = 4 * face + 2 * (1 if l1y < 0.0 else 0) + (1 if l1x * l1y < 0.0 else 0)
    f2 = 4 * face + 2 * (1 if l2y < 0.0 else 0) + (1 if l2x * l2y < 0.0 else 0)
    if f1 > f2:  # points ordered by feature id
        p1x, p1y, p2x, p2y, f1, f2 = p2x, p2y, p1x, p1y, f2, f1
    s1 = (p1x - centre_x) * ref_x + (p1y - centre_y) * ref_y
    s2 = (p2x - centre_x) * ref_x + (p2y - centre_y) * ref_y
    # Each point midway between the incident vertex and the reference face.
    c1x, c1y = p1x - 0.5 * s1 * ref_x, p1y - 0.5 * s1 * ref_y
    c2x, c2y = p2x - 0.5 * s2 * ref_x, p2y - 0.5 * s2 * ref_y
    first = (c1x - a[SX], c1y - a[SY], c1x - b[SX], c1y - b[SY], s1, f1)
    second = (c2x - a[SX], c2y - a[SY], c2x - b[SX], c2y - b[SY], s2, f2)
    kept = (1 if s1 < margin else 0) | (2 if s2 < margin else 0)
    nx, ny = (-ref_x, -ref_y) if ref_is_b else (ref_x, ref_y)
    return kept, nx, ny, first, second, NO_POINT, NO_POINT


#: The registry: pair kind -> (kind of A, kind of B, function). ``collide`` dispatches by it.
PAIRS = {
    CIRCLE_CIRCLE: (CIRCLE, CIRCLE, circle_circle),
    CIRCLE_BOX: (CIRCLE, BOX, circle_box),
    BOX_BOX: (BOX, BOX, box_box),
    CIRCLE_PLANE: (CIRCLE, PLANE, circle_plane),
    BOX_PLANE: (BOX, PLANE, box_plane),
    CIRCLE_POLYGON: (CIRCLE, POLYGON, circle_polygon),
    BOX_POLYGON: (BOX, POLYGON, polygon_polygon),
    POLYGON_POLYGON: (POLYGON, POLYGON, polygon_polygon),
    POLYGON_PLANE: (POLYGON, PLANE, polygon_plane),
}


@kernel
def pair_kind(kind_a, kind_b) -> int:
    """The entry of ``PAIRS`` for shapes of kinds ``kind_a <= kind_b`` (-1: none)."""
    if kind_a == CIRCLE:
        if kind_b == POLYGON:
            return CIRCLE_POLYGON
        return CIRCLE_CIRCLE if kind_b == CIRCLE else CIRCLE_BOX if kind_b == BOX else CIRCLE_PLANE
    if kind_a == BOX:
        return BOX_BOX if kind_b == BOX else BOX_POLYGON if kind_b == POLYGON else BOX_PLANE
    if kind_a == POLYGON:
        return POLYGON_POLYGON if kind_b == POLYGON else POLYGON_PLANE
    return -1


@kernel
def collide(kind, a, b, row_a, row_b, margin, tag):
    """The manifold of shapes ``a`` and ``b`` by the function ``PAIRS`` names for ``kind``.

    (Compiled code cannot look a function up in a dict, so the dispatch is written out;
    a test checks it against ``PAIRS``.)"""
    if kind == CIRCLE_CIRCLE:
        return circle_circle(a, b, row_a, row_b, margin, tag)
    if kind == CIRCLE_BOX:
        return circle_box(a, b, row_a, row_b, margin, tag)
    if kind == BOX_BOX:
        return box_box(a, b, row_a, row_b, margin, tag)
    if kind == CIRCLE_PLANE:
        return circle_plane(a, b, row_a, row_b, margin, tag)
    if kind == BOX_PLANE:
        return box_plane(a, b, row_a, row_b, margin, tag)
    if kind == CIRCLE_POLYGON:
        return circle_polygon(a, b, row_a, row_b, margin, tag)
    if kind == POLYGON_PLANE:
        return polygon_plane(a, b, row_a, row_b, margin, tag)
    return polygon_polygon(a, b, row_a, row_b, margin, tag)


@kernel
def anchor_kept(kind_a, kind_b, feature) -> float:
    """Which anchor of a point is a material point that moves with its body
    (``contacts.follow_bodies``): 0 A's, 1 B's, 2 both (two discs). A disc's point is on
    its surface below its centre; a box's or polygon's against a plane, its vertex; of two
    boxes or polygons, the incident one's vertex (box-box feature ids from 16 up, and
    polygon ones from ``B_REFERENCE`` up, have their reference face on B)."""
    if kind_a == CIRCLE:
        return 2.0 if kind_b == CIRCLE else 0.0
    if kind_b == BOX:
        return 0.0 if feature >= 16 else 1.0
    if kind_b == POLYGON:
        return 0.0 if feature >= B_REFERENCE else 1.0
    return 0.0


@kernel
def find_points(body, hull, shapes, w, ctx, terms, pairs, n_pairs, points, ids) -> int:
    """The points of every candidate pair, in pair order and, within a pair, by feature.
    A pair's margin is what the two can close this step plus their speculative distances.
    Returns the count (past the capacity of ``points``, only counted)."""
    dt = ctx[context.DT]
    no_outline = ctx[:0]  # the empty row every shape but a polygon is given
    count = 0
    for k in range(n_pairs):
        a, b = pairs[k, 0], pairs[k, 1]
        if shapes[b, 0] == PLANE:  # see broadphase.pushed_reach
            closing = terms[a, PUSHED] * dt
        else:
            closing = (terms[a, REACH] + terms[b, REACH]) * dt
        margin = terms[a, HALF_SPEC] + terms[b, HALF_SPEC] + closing
        row_a = hull[w, a] if shapes[a, 0] == POLYGON else no_outline
        row_b = hull[w, b] if shapes[b, 0] == POLYGON else no_outline
        manifold = collide(
            pair_kind(shapes[a, 0], shapes[b, 0]),
            shape_of(body, terms, w, a),
            shape_of(body, terms, w, b),
            row_a,
            row_b,
            margin,
            float(a * 65537 + b),
        )
        kept, nx, ny = manifold[0], manifold[1], manifold[2]
        found = (manifold[3], manifold[4], manifold[5], manifold[6])
        for j in range(4):
            if kept & (1 << j) == 0:
                continue
            if count < points.shape[0]:
                point = found[j]
                points[count, NX], points[count, NY] = nx, ny
                points[count, RAX], points[count, RAY] = point[0], point[1]
                points[count, RBX], points[count, RBY] = point[2], point[3]
                points[count, SEP0] = point[4]
                points[count, KEEP] = anchor_kept(shapes[a, 0], shapes[b, 0], point[5])
                points[count, AGAINST_PLANE] = 1.0 if shapes[b, 0] == PLANE else 0.0
                ids[count, 0], ids[count, 1], ids[count, 2] = a, b, point[5]
            count += 1
    return count
