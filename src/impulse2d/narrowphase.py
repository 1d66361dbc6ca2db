"""Narrowphase: contact points for candidate pairs, one vectorised function per shape pair.

Conventions, used throughout the engine:

* A pair ``(A, B)`` always has ``kind(A) <= kind(B)`` (circle < box < plane), so five
  functions cover every pair; plane-plane never collides.
* The normal ``n`` points from A to B. ``separation`` is the signed gap along it,
  negative when the shapes overlap.
* A point's anchors ``rA``, ``rB`` are its offsets from A's and B's centres, in world
  orientation. The point is midway between the two surfaces.
* A point is kept when ``separation < margin``: the margin is the *speculative*
  distance for the pair (how far the two can close during this step), so a fast body
  gets its contact one step before it would reach the surface and cannot tunnel.
* Each function returns points ordered by (pair, feature); feature ids (which vertex of
  which face) let the solver carry impulses over from the previous step. A pair has up
  to two points, except a box against a plane, which can have a speculative point at
  each corner.

Every function takes whole arrays of pairs of its kind and uses no Python loops.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .state import BOX, CIRCLE, PLANE

# Pair kinds; the order is the major key of the pair keys (see broadphase.py).
CIRCLE_CIRCLE, CIRCLE_BOX, BOX_BOX, CIRCLE_PLANE, BOX_PLANE = range(5)
PAIR_KIND = np.array(
    [
        [CIRCLE_CIRCLE, CIRCLE_BOX, CIRCLE_PLANE],
        [CIRCLE_BOX, BOX_BOX, BOX_PLANE],
        [CIRCLE_PLANE, BOX_PLANE, -1],
    ],
    dtype=np.int64,
)
PAIR_SHAPES = {
    CIRCLE_CIRCLE: (CIRCLE, CIRCLE),
    CIRCLE_BOX: (CIRCLE, BOX),
    BOX_BOX: (BOX, BOX),
    CIRCLE_PLANE: (CIRCLE, PLANE),
    BOX_PLANE: (BOX, PLANE),
}
FEATURES = 32  # feature ids are < 32 (box-box: 8 reference faces x 4 incident vertices)

_GOLDEN_ANGLE = np.pi * (3.0 - np.sqrt(5.0))


@dataclass
class Shapes:
    """The geometry of one side of a batch of pairs (fields unused by a kind are None)."""

    x: np.ndarray
    y: np.ndarray
    cos: np.ndarray | None = None  # rotation (boxes)
    sin: np.ndarray | None = None
    half_w: np.ndarray | None = None  # circle radius, or box half width
    half_h: np.ndarray | None = None
    normal_x: np.ndarray | None = None  # planes
    normal_y: np.ndarray | None = None
    vx: np.ndarray | None = None  # velocity (circles, for the time of impact)
    vy: np.ndarray | None = None


@dataclass
class Points:
    """Contact points of a batch of pairs. All arrays have one entry per point."""

    pair: np.ndarray  # index of the pair in the batch given to the function
    normal_x: np.ndarray
    normal_y: np.ndarray
    anchor_ax: np.ndarray
    anchor_ay: np.ndarray
    anchor_bx: np.ndarray
    anchor_by: np.ndarray
    separation: np.ndarray
    feature: np.ndarray  # int64 in [0, FEATURES)

    def take(self, rows: np.ndarray) -> Points:
        names = Points.__dataclass_fields__
        return Points(**{name: getattr(self, name)[rows] for name in names})

    @staticmethod
    def concatenate(parts: list[Points]) -> Points:
        names = Points.__dataclass_fields__
        return Points(**{name: np.concatenate([getattr(p, name) for p in parts]) for name in names})


def _points(keep: np.ndarray, pair: np.ndarray, *arrays: np.ndarray) -> Points:
    """Pack the kept rows (a boolean mask over flattened (pair, point) rows) into Points."""
    rows = np.flatnonzero(keep)
    picked = [np.asarray(a).reshape(-1)[rows] for a in arrays]
    return Points(pair.reshape(-1)[rows], *picked)


def circle_circle(a: Shapes, b: Shapes, margin: np.ndarray, tag: np.ndarray, dt: float) -> Points:
    """Two discs: one point, on the line of centres *where they will meet*.

    A speculative contact constrains motion along one normal: ``n . (relative motion) >=
    -separation``, a half-plane touching the disc of forbidden offsets. Taking ``n`` from
    the positions at the start of the step (the nearest points) is right for discs that
    close head on, but for two balls approaching at an angle it is not the line of centres
    when they touch, and the struck ball leaves a few degrees off (3 degrees at 4 m/s and
    60 Hz) or a ball grazing past is nudged by a collision that never happens. Discs move
    in straight lines within a step, so the half-plane is taken where it matters: at the
    time of impact ``t`` solving ``|d + u t| = R`` (``d`` the offset of the centres, ``u``
    their relative velocity, ``R`` the sum of radii) if they will meet, else at the time of
    closest approach; the separation is then ``n . d - R``.
    """
    dx, dy = b.x - a.x, b.y - a.y
    dist = np.hypot(dx, dy)
    reach_sum = a.half_w + b.half_w
    separation = dist - reach_sum
    # Pairs whose surfaces are farther apart than they can close this step are done.
    pair = np.flatnonzero(separation < margin)
    if pair.size < dx.size:
        dx, dy, dist, reach_sum = dx[pair], dy[pair], dist[pair], reach_sum[pair]
        separation = separation[pair]
    ux, uy = b.vx[pair] - a.vx[pair], b.vy[pair] - a.vy[pair]
    closing = dx * ux + dy * uy  # d . u < 0: approaching
    ahead = (separation > 0.0) & (closing < 0.0)
    dx_t, dy_t, length = dx, dy, dist
    if ahead.any():
        # Impact: u.u t^2 + 2 d.u t + (d.d - R^2) = 0, the first root; closest approach
        # (a miss): t = -d.u / u.u.
        speed2 = ux * ux + uy * uy
        safe2 = np.where(ahead, speed2, 1.0)
        disc = closing * closing - speed2 * (dist * dist - reach_sum * reach_sum)
        impact = (-closing - np.sqrt(np.maximum(disc, 0.0))) / safe2
        when = np.where(ahead, np.where(disc >= 0.0, impact, -closing / safe2), 0.0)
        dx_t, dy_t = dx + ux * when, dy + uy * when
        length = np.hypot(dx_t, dy_t)
    degenerate = length < 1e-12
    safe = np.where(degenerate, 1.0, length)
    nx, ny = dx_t / safe, dy_t / safe
    if degenerate.any():
        # Coincident centres have no line of centres. Pick a direction from the pair's tag
        # by the golden angle: deterministic, and different pairs get different directions,
        # so a pile spawned in one spot fans out in every direction, not along one axis.
        phi = tag[pair] * _GOLDEN_ANGLE
        nx, ny = np.where(degenerate, np.cos(phi), nx), np.where(degenerate, np.sin(phi), ny)
    separation = np.where(ahead, nx * dx + ny * dy - reach_sum, separation)
    # Anchors on the normal through each centre (midway between the surfaces), so the
    # normal impulse never turns a disc even when the impact normal is not the line of
    # centres now.
    half_a = a.half_w[pair] if pair.size < a.half_w.size else a.half_w
    reach_a = half_a + 0.5 * separation
    reach_b = -(reach_sum - half_a + 0.5 * separation)
    rax, ray, rbx, rby = nx * reach_a, ny * reach_a, nx * reach_b, ny * reach_b
    return Points(pair, nx, ny, rax, ray, rbx, rby, separation, np.zeros(pair.size, np.int64))


def circle_box(a: Shapes, b: Shapes, margin: np.ndarray, tag: np.ndarray, dt: float) -> Points:
    """Disc A against box B: closest point on the box, or the nearest face if inside."""
    c, s, hw, hh, r = b.cos, b.sin, b.half_w, b.half_h, a.half_w
    dx, dy = a.x - b.x, a.y - b.y  # circle centre relative to the box, world frame
    px, py = c * dx + s * dy, -s * dx + c * dy  # ... in the box frame
    qx, qy = np.clip(px, -hw, hw), np.clip(py, -hh, hh)
    ox, oy = px - qx, py - qy
    dist = np.hypot(ox, oy)
    outside = dist > 0.0
    # Inside: push out through the face of least penetration.
    depth_x, depth_y = hw - np.abs(px), hh - np.abs(py)
    through_x = depth_x <= depth_y
    sx, sy = np.where(px >= 0.0, 1.0, -1.0), np.where(py >= 0.0, 1.0, -1.0)
    safe = np.where(outside, dist, 1.0)
    # Local normal from the box towards the circle, and the box surface point.
    lnx = np.where(outside, ox / safe, np.where(through_x, sx, 0.0))
    lny = np.where(outside, oy / safe, np.where(through_x, 0.0, sy))
    surface_x = np.where(outside, qx, np.where(through_x, sx * hw, px))
    surface_y = np.where(outside, qy, np.where(through_x, py, sy * hh))
    separation = np.where(outside, dist, -np.where(through_x, depth_x, depth_y)) - r
    nx, ny = -(c * lnx - s * lny), -(s * lnx + c * lny)  # A -> B: circle towards box
    box_x, box_y = c * surface_x - s * surface_y, s * surface_x + c * surface_y
    # Midpoint of the box surface point (B + box) and the circle's (A + r n), from A.
    rax, ray = 0.5 * (box_x - dx + r * nx), 0.5 * (box_y - dy + r * ny)
    pair = np.arange(dx.size)
    return _points(
        separation < margin,
        pair,
        nx,
        ny,
        rax,
        ray,
        rax + dx,
        ray + dy,
        separation,
        np.zeros(dx.size, np.int64),
    )


def box_box(a: Shapes, b: Shapes, margin: np.ndarray, tag: np.ndarray, dt: float) -> Points:
    """Two boxes by separating axes, with up to two points clipped from the incident edge.

    The axis of least penetration (or greatest separation) among the four face normals
    picks a *reference* face; the face of the other box most opposed to it is the
    *incident* face, whose edge is clipped to the reference face's extent (Sutherland-
    Hodgman against the two side planes). A's faces are preferred unless B's are clearly
    better (5 % relative, 1 % of the box size absolute): without that preference the
    reference face flips between frames for boxes resting flat, and warm starting
    loses its impulses.
    """
    ca, sa, cb, sb = a.cos, a.sin, b.cos, b.sin
    hwa, hha, hwb, hhb = a.half_w, a.half_h, b.half_w, b.half_h
    dx, dy = b.x - a.x, b.y - a.y
    dax, day = dx * ca + dy * sa, -dx * sa + dy * ca  # B's centre in A's frame
    dbx, dby = dx * cb + dy * sb, -dx * sb + dy * cb  # ... projected on B's axes
    # |R_A^T R_B|: the rotation between the boxes has entries (c00, c01; -c01, c00).
    a00 = np.abs(ca * cb + sa * sb)
    a01 = np.abs(sa * cb - ca * sb)
    separations = (
        np.abs(dax) - hwa - (hwb * a00 + hhb * a01),
        np.abs(day) - hha - (hwb * a01 + hhb * a00),
        np.abs(dbx) - hwb - (hwa * a00 + hha * a01),
        np.abs(dby) - hhb - (hwa * a01 + hha * a00),
    )
    sizes = (hwa, hha, hwb, hhb)
    axis = np.zeros(dx.size, np.int64)
    best = separations[0]
    for index in (1, 2, 3):
        better = separations[index] > best + 0.05 * np.abs(best) + 0.01 * sizes[index]
        axis = np.where(better, index, axis)
        best = np.where(better, separations[index], best)

    # Reference face: outward normal n_ref (towards the incident box), tangent t along the
    # face, the face's distance from its box centre, and its half length.
    sign = np.choose(axis, (dax, day, dbx, dby)) >= 0.0
    sign = np.where(sign, 1.0, -1.0)
    flip = np.where(axis >= 2, -sign, sign)  # B's faces point from B towards A
    ref_x = flip * np.choose(axis, (ca, -sa, cb, -sb))
    ref_y = flip * np.choose(axis, (sa, ca, sb, cb))
    tan_x, tan_y = -ref_y, ref_x
    offset = np.choose(axis, (hwa, hha, hwb, hhb))
    side = np.choose(axis, (hha, hwa, hhb, hwb))
    ref_is_b = axis >= 2
    centre_x = np.where(ref_is_b, b.x, a.x) + offset * ref_x  # centre of the reference face
    centre_y = np.where(ref_is_b, b.y, a.y) + offset * ref_y

    # Incident face: the face of the other box whose normal is most opposed to n_ref.
    ic, is_ = np.where(ref_is_b, ca, cb), np.where(ref_is_b, sa, sb)
    ihw, ihh = np.where(ref_is_b, hwa, hwb), np.where(ref_is_b, hha, hhb)
    ix, iy = np.where(ref_is_b, a.x, b.x), np.where(ref_is_b, a.y, b.y)
    along_x = ref_x * ic + ref_y * is_  # n_ref . (incident box x axis)
    along_y = -ref_x * is_ + ref_y * ic
    x_face = np.abs(along_x) >= np.abs(along_y)
    face_sign = -np.where(np.where(x_face, along_x, along_y) >= 0.0, 1.0, -1.0)
    # The incident edge's two vertices in the incident box's frame.
    l1x = np.where(x_face, face_sign * ihw, ihw)
    l1y = np.where(x_face, ihh, face_sign * ihh)
    l2x = np.where(x_face, face_sign * ihw, -ihw)
    l2y = np.where(x_face, -ihh, face_sign * ihh)
    v1x, v1y = ix + ic * l1x - is_ * l1y, iy + is_ * l1x + ic * l1y
    v2x, v2y = ix + ic * l2x - is_ * l2y, iy + is_ * l2x + ic * l2y

    # Clip the edge to the reference face's extent [-side, side] along t.
    u1 = (v1x - centre_x) * tan_x + (v1y - centre_y) * tan_y
    u2 = (v2x - centre_x) * tan_x + (v2y - centre_y) * tan_y
    missed = ((u1 > side) & (u2 > side)) | ((u1 < -side) & (u2 < -side))
    span = np.where(u2 == u1, 1.0, u2 - u1)
    lam1 = (np.clip(u1, -side, side) - u1) / span  # fraction from v1 towards v2
    lam2 = (np.clip(u2, -side, side) - u2) / -span  # fraction from v2 towards v1
    p1x, p1y = v1x + lam1 * (v2x - v1x), v1y + lam1 * (v2y - v1y)
    p2x, p2y = v2x + lam2 * (v1x - v2x), v2y + lam2 * (v1y - v2y)
    sep1 = (p1x - centre_x) * ref_x + (p1y - centre_y) * ref_y
    sep2 = (p2x - centre_x) * ref_x + (p2y - centre_y) * ref_y

    # Feature ids: reference face (axis and side: 8) x incident vertex (4, counter-clockwise
    # from (+, +)); a vertex's id is 2 [y < 0] + [x y < 0].
    face = 2 * axis + (sign < 0.0)
    vid1 = 2 * (l1y < 0.0) + (l1x * l1y < 0.0)
    vid2 = 2 * (l2y < 0.0) + (l2x * l2y < 0.0)
    f1, f2 = 4 * face + vid1, 4 * face + vid2
    swap = f1 > f2  # order the two points by feature id
    ok = ~missed & (best < margin)

    def ordered(first: np.ndarray, second: np.ndarray) -> np.ndarray:
        return np.stack([np.where(swap, second, first), np.where(swap, first, second)], axis=1)

    px, py = ordered(p1x, p2x), ordered(p1y, p2y)
    sep = ordered(sep1, sep2)
    features = ordered(f1, f2).astype(np.int64)
    keep = (sep < margin[:, None]) & ok[:, None]
    # The point midway between the incident vertex and the reference face.
    cx = px - 0.5 * sep * ref_x[:, None]
    cy = py - 0.5 * sep * ref_y[:, None]
    nx = np.where(ref_is_b, -ref_x, ref_x)[:, None]
    ny = np.where(ref_is_b, -ref_y, ref_y)[:, None]
    rax, ray = cx - a.x[:, None], cy - a.y[:, None]
    rbx, rby = cx - b.x[:, None], cy - b.y[:, None]
    pair = np.repeat(np.arange(dx.size), 2).reshape(-1, 2)
    nx, ny = np.broadcast_to(nx, keep.shape), np.broadcast_to(ny, keep.shape)
    return _points(keep, pair, nx, ny, rax, ray, rbx, rby, sep, features)


# Box corners in counter-clockwise order from (+, +); their index is the feature id.
_CORNER_X = np.array([1.0, -1.0, -1.0, 1.0])
_CORNER_Y = np.array([1.0, 1.0, -1.0, -1.0])


def box_plane(a: Shapes, b: Shapes, margin: np.ndarray, tag: np.ndarray, dt: float) -> Points:
    """Box A against half-space B: every corner within the margin (up to four).

    A resting box has two (its lower corners); a box spinning fast near the ground can
    have three or four, and each must be a speculative contact or the corner that is
    about to swing down would pass through the ground within the step.
    """
    c, s = a.cos[:, None], a.sin[:, None]
    lx, ly = a.half_w[:, None] * _CORNER_X, a.half_h[:, None] * _CORNER_Y
    rx, ry = c * lx - s * ly, s * lx + c * ly  # corner offsets, world frame (K, 4)
    plane_nx, plane_ny = b.normal_x[:, None], b.normal_y[:, None]
    base = (a.x - b.x)[:, None] * plane_nx + (a.y - b.y)[:, None] * plane_ny
    sep = base + rx * plane_nx + ry * plane_ny  # signed distance of each corner
    cx = rx - 0.5 * sep * plane_nx
    cy = ry - 0.5 * sep * plane_ny
    keep = sep < margin[:, None]
    pair = np.repeat(np.arange(a.x.size), 4).reshape(-1, 4)
    corners = np.broadcast_to(np.arange(4), keep.shape)
    nx = np.broadcast_to(-plane_nx, keep.shape)
    ny = np.broadcast_to(-plane_ny, keep.shape)
    offset_x, offset_y = (a.x - b.x)[:, None], (a.y - b.y)[:, None]
    return _points(keep, pair, nx, ny, cx, cy, cx + offset_x, cy + offset_y, sep, corners)


def circle_plane(a: Shapes, b: Shapes, margin: np.ndarray, tag: np.ndarray, dt: float) -> Points:
    """Disc A against half-space B: one point below the centre."""
    nx, ny = b.normal_x, b.normal_y
    separation = (a.x - b.x) * nx + (a.y - b.y) * ny - a.half_w
    reach = a.half_w + 0.5 * separation
    rax, ray = -nx * reach, -ny * reach
    pair = np.arange(a.x.size)
    return _points(
        separation < margin,
        pair,
        -nx,
        -ny,
        rax,
        ray,
        rax + a.x - b.x,
        ray + a.y - b.y,
        separation,
        np.zeros(a.x.size, np.int64),
    )


CollideFn = Callable[[Shapes, Shapes, np.ndarray, np.ndarray, float], Points]

#: The narrowphase table: pair kind -> function. Chosen by table, not by double dispatch.
COLLIDE: dict[int, CollideFn] = {
    CIRCLE_CIRCLE: circle_circle,
    CIRCLE_BOX: circle_box,
    BOX_BOX: box_box,
    CIRCLE_PLANE: circle_plane,
    BOX_PLANE: box_plane,
}
