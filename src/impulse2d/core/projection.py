"""Stage: the bodies that a step left deep inside a plane are moved out of it.

The velocity solve keeps contacts apart through constraints linearised at the step's
start: a corner's approach is ``v + w x r`` with the lever ``r`` of the start pose. When
a body turns far within one step (a light plank knocked over by a heavy ball turns a
radian in one 30 ms step at one substep), the corner that swings down moves along an
arc the linear constraint does not see, and it can end the step deeper in the ground
than the soft contact recovers from before the centre is behind it. Box2D v2 answers
this with a position solver (non-linear Gauss-Seidel: constraints re-evaluated at the
current pose); this stage is its part that matters most here, for planes, which nothing
pushes back: after the substeps, a dynamic body whose deepest point is more than
``DEEPEST_FRACTION`` of its smallest half size inside a plane it has a point against is
moved, by the shortest translation, until it is at most that deep in each of its planes
(in a corner of two planes, along neither normal alone: each move would push it into
the other). Its velocity is not
touched (kinetic energy unchanged; the relax pass already left its points not closing).

The allowance is far beyond the soft contact's usual overlap (a resting body sinks by
about its weight over the contact stiffness, micrometres), so a normal step never moves
anything here; it only acts where the linearisation failed. A body squeezed between a
plane and a kinematic pusher also ends here in front of the plane (overlapping the
pusher instead, which the next step's contact pushes apart again): a plane is the one
thing no contact can move.

With the deepest point of a body at most half its smallest half size ``s`` in, its
centre is at least ``s / 2`` in front: the support distance of a box or disc along any
normal is at least ``s`` (a polygon's half sizes are both its inner radius: the
distance from its centre of mass to its nearest edge, plus its rounding).
"""

from __future__ import annotations

import math

from ._jit import kernel
from .state import (
    ANGLE,
    BOX,
    HALF_H,
    HALF_W,
    INV_MASS,
    NORMAL_X,
    NORMAL_Y,
    PLANE,
    POLYGON,
    ROUNDING,
    VERTEX0,
    VERTEX_COUNT,
    X,
    Y,
)
from .workspace import AGAINST_PLANE

DEEPEST_FRACTION = 0.5  # of the body's smallest half size: the deepest point allowed in a plane
_MAX_PLANES = 8  # planes looked at per body (more is a scene of its own)


@kernel
def depth_in_plane(body, hull, shapes, w, i, plane) -> float:
    """How far (m) the deepest point of body ``i`` is behind the plane (< 0: in front),
    at its current pose: its support distance along the normal minus its centre's."""
    nx, ny = body[w, plane, NORMAL_X], body[w, plane, NORMAL_Y]
    centre = (body[w, i, X] - body[w, plane, X]) * nx + (body[w, i, Y] - body[w, plane, Y]) * ny
    hw, hh = body[w, i, HALF_W], body[w, i, HALF_H]
    if shapes[i, 0] == POLYGON:  # its farthest vertex along -n, and its rounding
        c, s = math.cos(body[w, i, ANGLE]), math.sin(body[w, i, ANGLE])
        deepest = -math.inf
        for k in range(int(hull[w, i, VERTEX_COUNT])):
            lx, ly = hull[w, i, VERTEX0 + 2 * k], hull[w, i, VERTEX0 + 2 * k + 1]
            deepest = max(deepest, -(nx * (c * lx - s * ly) + ny * (s * lx + c * ly)))
        return deepest + hull[w, i, ROUNDING] - centre
    if shapes[i, 0] != BOX:
        return hw - centre  # a disc: its radius
    c, s = math.cos(body[w, i, ANGLE]), math.sin(body[w, i, ANGLE])
    # The box's axes (c, s) and (-s, c): the corner farthest along -n lies
    # hw |n . x_axis| + hh |n . y_axis| from the centre.
    return hw * abs(nx * c + ny * s) + hh * abs(-nx * s + ny * c) - centre


@kernel
def _plane(body, hull, shapes, w, ids, n, i, first, allowed, j):
    """``(n_x, n_y, excess, count)`` of body ``i``'s plane ``j``: its planes are the
    distinct planes of its pairs (which start at point ``first``), in point order, at
    most ``_MAX_PLANES``; ``excess`` is how much deeper than ``allowed`` the body is in
    it; ``count`` how many planes come before ``j`` (all of them, with zeros, for ``j``
    past the last). Looked up again where needed rather than gathered into arrays: the
    step allocates nothing (a GPU kernel cannot), and a body has few planes."""
    m = 0
    for k in range(first, n):
        if ids[k, 0] != i:
            break
        plane = ids[k, 1]
        if shapes[plane, 0] != PLANE or (k > first and ids[k - 1, 1] == plane) or m == _MAX_PLANES:
            continue
        if m == j:
            excess = depth_in_plane(body, hull, shapes, w, i, plane) - allowed
            return body[w, plane, NORMAL_X], body[w, plane, NORMAL_Y], excess, m
        m += 1
    return 0.0, 0.0, 0.0, m


@kernel
def _worst_excess(body, hull, shapes, w, ids, n, i, first, allowed, m, tx, ty) -> float:
    """The largest ``excess_j - n_j . t`` over the ``m`` planes: how much deeper than
    allowed the body stays after the move ``t`` (<= 0: nowhere)."""
    worst = -math.inf
    for j in range(m):
        nx, ny, excess, _ = _plane(body, hull, shapes, w, ids, n, i, first, allowed, j)
        worst = max(worst, excess - (nx * tx + ny * ty))
    return worst


@kernel
def _smallest_move(body, hull, shapes, w, ids, n, i, first, allowed, m):
    """The shortest translation ``t`` with ``n_j . t >= excess_j`` for the ``m`` planes of
    body ``i`` (``_plane``: a move along ``n_j`` takes the body out of plane ``j``;
    ``excess_j`` how much deeper it is than allowed, negative for the planes it is clear
    of, which it must stay clear of). A least-norm problem over half-planes in 2-D: its
    answer has at most two constraints active, so it is one of ``excess_j n_j`` or the
    corner where two are met exactly, and the candidates are few. If none meets them all
    (a body in a wedge of planes narrower than itself), the one that leaves the least
    excess."""
    where = (body, hull, shapes, w, ids, n, i, first, allowed)
    best_x = best_y = 0.0
    best_norm, best_worst = math.inf, _worst_excess(*where, m, 0.0, 0.0)
    tolerance = 1e-9 * (1.0 + max(abs(best_worst), 0.0))
    if best_worst <= 0.0:
        return 0.0, 0.0
    for j in range(m):
        nxj, nyj, excess_j, _ = _plane(*where, j)
        for k in range(j, m):
            nxk, nyk, excess_k, _ = _plane(*where, k)
            if k == j:
                tx, ty = excess_j * nxj, excess_j * nyj
            else:
                det = nxj * nyk - nyj * nxk
                if abs(det) < 1e-9:
                    continue  # parallel planes: no corner
                tx = (excess_j * nyk - excess_k * nyj) / det
                ty = (nxj * excess_k - nxk * excess_j) / det
            worst, norm = _worst_excess(*where, m, tx, ty), math.hypot(tx, ty)
            feasible, best_feasible = worst <= tolerance, best_worst <= tolerance
            if (feasible and (not best_feasible or norm < best_norm)) or (
                not feasible and not best_feasible and worst < best_worst
            ):
                best_x, best_y, best_norm, best_worst = tx, ty, norm, worst
    return best_x, best_y


@kernel
def _project_body(body, hull, shapes, w, ids, n, i, first) -> None:
    """Move body ``i`` (its pairs start at point ``first``) out of its planes, at most
    ``_MAX_PLANES`` of them (the first by slot)."""
    allowed = DEEPEST_FRACTION * min(body[w, i, HALF_W], body[w, i, HALF_H])
    m = _plane(body, hull, shapes, w, ids, n, i, first, allowed, _MAX_PLANES)[3]
    tx, ty = _smallest_move(body, hull, shapes, w, ids, n, i, first, allowed, m)
    body[w, i, X] += tx
    body[w, i, Y] += ty


@kernel
def project_out_of_planes(body, hull, shapes, w, points, ids, n) -> None:
    """Move every dynamic body deeper in a plane it has a point against than
    ``DEEPEST_FRACTION`` of its smallest half size, by the shortest translation that
    leaves it at most that deep in each of its planes (``_smallest_move``). Points are
    sorted by body A, and a plane is always B: a body's pairs are consecutive."""
    first, current, done = 0, -1, False
    for k in range(n):
        i = ids[k, 0]
        if i != current:
            first, current, done = k, i, False
        if done or points[k, AGAINST_PLANE] != 1.0 or body[w, i, INV_MASS] == 0.0:
            continue
        allowed = DEEPEST_FRACTION * min(body[w, i, HALF_W], body[w, i, HALF_H])
        if depth_in_plane(body, hull, shapes, w, i, ids[k, 1]) > allowed:
            _project_body(body, hull, shapes, w, ids, n, i, first)
            done = True
