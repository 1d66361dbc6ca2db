"""Convex polygons, optionally rounded: the rules a vertex list must keep, and its mass
properties. The shapes of issue 37 (``Polygon``, capsules as rounded segments) are built
on these; ``Box`` keeps its closed forms, which these functions reproduce.

Vertices are in body coordinates (m), one row ``(x, y)`` each. The rules, and why:

* 3 to ``MAX_VERTICES`` (8) vertices, as Box2D v3 allows: the narrowphase keeps a fixed
  row per shape, and clipping stays short;
* finite numbers, and no edge shorter than ``MIN_EDGE`` (m): a degenerate edge has no
  normal, and a contact on it none either;
* counter-clockwise. A clockwise list is reversed (its first vertex stays first): the
  order is only a convention, so there is one obvious way to read a clockwise list,
  and the polygon is the same set of points. Nothing else is reordered;
* strictly convex: every corner turns left by more than ``MIN_TURN`` (the sine of the
  angle between the edges meeting there). A collinear vertex is refused rather than
  dropped, since the user's vertex numbering (features, drawings) would change under
  them; a reflex one makes the shape non-convex, which the solver cannot collide;
* a rounding ``radius`` (m) >= 0: the shape is every point within ``radius`` of the
  polygon (a capsule is a rounded two-vertex segment; the segment functions elsewhere).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _checks

__all__ = ["MAX_VERTICES", "MIN_EDGE", "MIN_TURN", "MassProperties", "check_polygon", "mass"]

MAX_VERTICES = 8
MIN_EDGE = 0.005  # m: Box2D's linear slop, the smallest length its solver resolves
MIN_TURN = 1e-6  # sine of a corner's turn: below it the corner counts as straight


class MassProperties(NamedTuple):
    """A shape's area (m^2), its centroid (m, body coordinates) and its second moment of
    area about the centroid (m^4): mass = density * area, inertia = density * moment."""

    area: float
    centroid: tuple[float, float]
    moment: float


def _cross(ax: float, ay: float, bx: float, by: float) -> float:
    return ax * by - ay * bx


def check_polygon(vertices: ArrayLike, radius: float = 0.0) -> NDArray[np.float64]:
    """The vertices as a counter-clockwise (n, 2) float64 array, or a ``ValueError``
    naming the rule broken (this module's docstring)."""
    points = _checks.real_array("vertices", vertices)
    if points.ndim != 2 or points.shape[1] != 2:
        raise ValueError(f"vertices must be a list of (x, y) pairs, got shape {points.shape}")
    n = len(points)
    if not 3 <= n <= MAX_VERTICES:
        raise ValueError(f"vertices must number 3 to {MAX_VERTICES}, got {n}")
    if not np.isfinite(points).all():
        raise ValueError(f"vertices must be finite, got {points.tolist()}")
    if not (math.isfinite(radius) and radius >= 0.0):
        raise ValueError(f"radius must be >= 0 and finite, got {radius}")
    edges = np.roll(points, -1, axis=0) - points
    lengths = np.sqrt(edges[:, 0] * edges[:, 0] + edges[:, 1] * edges[:, 1])
    if lengths.min() < MIN_EDGE:
        i = int(lengths.argmin())
        raise ValueError(
            f"vertices must be at least {MIN_EDGE} m apart: edge {i}-{(i + 1) % n} is "
            f"{lengths[i]:.3g} m long"
        )
    turns = [_cross(*edges[i - 1], *edges[i]) / (lengths[i - 1] * lengths[i]) for i in range(n)]
    if all(t < -MIN_TURN for t in turns):  # every corner turns right: clockwise
        return np.concatenate([points[:1], points[:0:-1]])
    for i, turn in enumerate(turns):
        if turn <= MIN_TURN:
            what = "is collinear with its neighbours" if abs(turn) <= MIN_TURN else "turns back"
            raise ValueError(
                f"vertices must make a strictly convex polygon: vertex {i} "
                f"{tuple(points[i].tolist())} {what}"
            )
    # A list whose corners all turn left can still wind twice round (a pentagram):
    # the turning angles of a simple convex polygon add up to one full turn.
    total = sum(math.atan2(_cross(*edges[i - 1], *edges[i]), float(edges[i - 1] @ edges[i]))
                for i in range(n))  # fmt: skip
    if abs(total - 2.0 * math.pi) > 1e-6:
        raise ValueError("vertices must make a simple convex polygon: they wind round twice")
    return points


def mass(vertices: ArrayLike, radius: float = 0.0) -> MassProperties:
    """Area, centroid and second moment about the centroid of the convex polygon
    ``vertices`` (checked by ``check_polygon``) rounded by ``radius``.

    The polygon as a fan of triangles ``(o, a, b)`` from the origin, one per edge
    ``a -> b``: a triangle's area is ``A = (a x b) / 2``, its centroid ``(a + b) / 3``
    and its second moment about ``o`` is ``A (a.a + a.b + b.b) / 6``. The rounding adds,
    exactly, a rectangle of the edge's length and width ``r`` on each edge (outward,
    along the edge's normal) and a circular sector of radius ``r`` at each vertex, whose
    angles add up to ``2 pi``."""
    points = check_polygon(vertices, radius)
    area = moment_o = 0.0  # second moment about the origin, summed over the pieces
    first = np.zeros(2)  # first moment: area * centroid
    for a, b in zip(points, np.roll(points, -1, axis=0), strict=True):
        piece = 0.5 * _cross(*a, *b)
        area += piece
        first += piece * (a + b) / 3.0
        moment_o += piece * (a @ a + a @ b + b @ b) / 6.0
    if radius > 0.0:
        area, first, moment_o = _rounding(points, radius, area, first, moment_o)
    centroid = first / area
    moment = moment_o - area * float(centroid @ centroid)  # parallel axes
    return MassProperties(area, (float(centroid[0]), float(centroid[1])), moment)


def _rounding(
    points: NDArray[np.float64], r: float, area: float, first: NDArray, moment_o: float
) -> tuple[float, NDArray, float]:
    """Add the edge rectangles and the corner sectors of the rounding (``mass``)."""
    n = len(points)
    normals = []
    for i in range(n):
        a, b = points[i], points[(i + 1) % n]
        edge = b - a
        length = math.sqrt(float(edge @ edge))
        normal = np.array([edge[1], -edge[0]]) / length  # outward for counter-clockwise
        normals.append(normal)
        # The rectangle: centroid at the edge's middle pushed out by r / 2; its own
        # second moment (|e|^2 + r^2) / 12 per area.
        piece, centre = length * r, 0.5 * (a + b) + 0.5 * r * normal
        area += piece
        first += piece * centre
        moment_o += piece * ((length * length + r * r) / 12.0 + float(centre @ centre))
    for i in range(n):
        before, after = normals[i - 1], normals[i]
        angle = math.atan2(_cross(*before, *after), float(before @ after))  # in (0, pi)
        # A sector of angle t and radius r about its apex v: area t r^2 / 2, centroid at
        # 4 r sin(t / 2) / (3 t) along its bisector, second moment about v  t r^4 / 4.
        piece = 0.5 * angle * r * r
        bisector = (before + after) / math.sqrt(float((before + after) @ (before + after)))
        offset = 4.0 * r * math.sin(0.5 * angle) / (3.0 * angle)
        centre = points[i] + offset * bisector
        own = 0.25 * angle * r**4 - piece * offset * offset  # about the sector's centroid
        area += piece
        first += piece * centre
        moment_o += own + piece * float(centre @ centre)
    return area, first, moment_o
