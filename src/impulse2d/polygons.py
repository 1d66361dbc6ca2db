"""Shapes beyond the tutorial's: ``Polygon`` (convex, 3-8 vertices, optionally rounded),
``Capsule`` (a rounded segment) and ``Segment`` (a fixed line, for terrain).

All three are outlines to the engine (``core.outlines``): a row of ``state.hull`` with the
vertices, the edges' outward normals and the rounding radius, in the body's frame. As for
every body in impulse2d, that frame's origin is the centre of mass and ``position`` is
where the centre of mass is: a polygon's vertices are centred on their centroid when it
is made (``Polygon.vertices`` gives them so, in the order given), and ``Polygon.placed``
makes a polygon whose outline lies exactly on given world points.

An outline is fixed once made (``vertices``, ``radius`` and ``length`` cannot be set
later: the contact cache's feature ids number its edges), and the same in every world
of a batch; a different outline is a different body.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _checks, envelope, geometry
from .columns import COORDINATE
from .core.state import (
    BOUND_RADIUS,
    DYNAMIC,
    EDGE_NORMAL0,
    HULL_F,
    POLYGON,
    ROUNDING,
    UNIT_MOMENT,
    VERTEX0,
    VERTEX_COUNT,
)
from .shapes import Body

__all__ = ["Capsule", "Polygon", "Segment", "outline_row"]


def outline_row(
    vertices: NDArray[np.float64], radius: float, unit_moment: float
) -> NDArray[np.float64]:
    """The ``state.hull`` row of an outline: ``vertices`` (n, 2) counter-clockwise about
    the centre of mass, its rounding ``radius`` and moment per kg ``unit_moment``."""
    row = np.zeros(HULL_F)
    n = len(vertices)
    row[VERTEX_COUNT], row[ROUNDING], row[UNIT_MOMENT] = n, radius, unit_moment
    row[BOUND_RADIUS] = float(np.hypot(vertices[:, 0], vertices[:, 1]).max()) + radius
    row[VERTEX0 : VERTEX0 + 2 * n] = vertices.ravel()
    edges = np.roll(vertices, -1, axis=0) - vertices
    normals = np.column_stack([edges[:, 1], -edges[:, 0]])  # outward for counter-clockwise
    normals /= np.hypot(normals[:, 0], normals[:, 1])[:, None]
    row[EDGE_NORMAL0 : EDGE_NORMAL0 + 2 * n] = normals.ravel()
    return row


def inner_radius(row: NDArray[np.float64]) -> float:
    """The distance from the centre of mass to the outline's nearest edge line, plus its
    rounding: the largest disc about the centre inside the shape (m)."""
    n = int(row[VERTEX_COUNT])
    vertices = row[VERTEX0 : VERTEX0 + 2 * n].reshape(n, 2)
    normals = row[EDGE_NORMAL0 : EDGE_NORMAL0 + 2 * n].reshape(n, 2)
    return max(float(np.min(np.sum(vertices * normals, axis=1))), 0.0) + float(row[ROUNDING])


class _Outline(Body):
    """What Polygon, Capsule and Segment share: an outline row, its containment test."""

    _kind = POLYGON
    _outline: NDArray[np.float64]

    def _set_outline(self, vertices: NDArray[np.float64], radius: float, moment: float) -> None:
        row = outline_row(vertices, radius, moment)
        size = envelope.SIZE
        if row[BOUND_RADIUS] > size[1]:
            raise ValueError(
                f"{type(self).__name__} must fit within {size[1]:g} m of its centre of mass,"
                f" got {row[BOUND_RADIUS]:g} m"
            )
        self._outline = row
        thickness = 2.0 * inner_radius(row)
        if self._motion == DYNAMIC and thickness < size[0]:
            # A sliver has no interior for the solver to push out of.
            raise ValueError(
                f"{type(self).__name__} must be at least {size[0]:g} m thick to be dynamic,"
                f" got {thickness:g} m"
            )

    @property
    def radius(self) -> float:
        """Rounding radius (m): every point within it of the polygon is solid."""
        return float(self._outline[ROUNDING])

    def _moment_of(self, mass: Any) -> Any:
        return mass * self._outline[UNIT_MOMENT]

    def _contains_local(self, local: np.ndarray) -> Any:
        inside = contains(self._outline, local)
        return bool(inside) if inside.ndim == 0 else inside


def contains(row: NDArray[np.float64], local: np.ndarray) -> np.ndarray:
    """Whether body-frame points ``local`` (..., 2) lie in the outline ``row``: within its
    rounding of the polygon (inside every edge line, or that near an edge)."""
    n = int(row[VERTEX_COUNT])
    vertices = row[VERTEX0 : VERTEX0 + 2 * n].reshape(n, 2)
    normals = row[EDGE_NORMAL0 : EDGE_NORMAL0 + 2 * n].reshape(n, 2)
    p = np.asarray(local, float)[..., None, :]  # (..., 1, 2) against (n, 2)
    gaps = np.sum((p - vertices) * normals, axis=-1)
    start, edge = vertices, np.roll(vertices, -1, axis=0) - vertices
    t = np.clip(np.sum((p - start) * edge, axis=-1) / np.sum(edge * edge, axis=-1), 0.0, 1.0)
    nearest = np.hypot(*np.moveaxis(p - start - t[..., None] * edge, -1, 0)).min(axis=-1)
    core = gaps.max(axis=-1) <= 0.0 if n > 2 else np.zeros(nearest.shape, bool)
    return core | (nearest <= row[ROUNDING])


class Polygon(_Outline):
    """A solid convex polygon of 3 to 8 ``vertices`` (m, body frame), rounded by
    ``radius`` (m, >= 0; default 0: sharp corners).

    The vertices follow ``geometry.check_polygon``'s rules (counter-clockwise, a clockwise
    list reversed keeping its first vertex; strictly convex; no edge under 5 mm); they
    are centred on their centroid, which is the centre of mass and ``position`` (see the
    module docstring). Mass properties are exact (``geometry.mass``). All other keywords
    as in :class:`Body`. Example::

        wedge = world.add(Polygon(vertices=[(0, 0), (1, 0), (0, 0.5)], position=(2, 1)))
    """

    def __init__(self, *, vertices: ArrayLike, radius: float = 0.0, **body: Any) -> None:
        super().__init__(**body)
        radius = _checks.non_negative("radius", radius)
        _checks.within("radius", radius, 0.0, envelope.SIZE[1], unit=" m")
        points = geometry.check_polygon(vertices, radius)
        area, centroid, moment = geometry.mass(points, radius)
        self._set_outline(points - np.array(centroid), radius, moment / area)

    @classmethod
    def placed(cls, vertices: ArrayLike, **body: Any) -> Polygon:
        """A polygon whose outline lies on the world points ``vertices`` (its
        ``position`` is their centroid; the other keywords as for ``Polygon``)."""
        if "position" in body:
            raise ValueError("placed takes the outline's world points; leave position out")
        points = geometry.check_polygon(vertices, body.get("radius", 0.0))
        centroid = geometry.mass(points, float(body.get("radius", 0.0))).centroid
        angle = _checks.finite_scalar("angle", body.pop("angle", 0.0))
        c, s = math.cos(angle), math.sin(angle)
        local = (points - np.array(centroid)) @ np.array([[c, -s], [s, c]])  # R^T p
        return cls(vertices=local, position=centroid, angle=angle, **body)

    @property
    def vertices(self) -> NDArray[np.float64]:
        """The vertices (n, 2) in the body frame (m), centred on the centre of mass."""
        n = int(self._outline[VERTEX_COUNT])
        return self._outline[VERTEX0 : VERTEX0 + 2 * n].reshape(n, 2).copy()

    def world_vertices(self) -> NDArray[np.float64]:
        """The vertices in world coordinates: (n, 2), or (B, n, 2) in a batch."""
        points = [self.to_world(v) for v in self.vertices]
        return np.stack(points, axis=-2)


class _Rod(_Outline):
    """What Capsule and Segment share: an outline of two vertices ``length`` apart along
    the body's x axis, about its centre."""

    _length: float

    def _set_rod(self, length: float, radius: float) -> None:
        self._length = length
        ends = np.array([[-0.5 * length, 0.0], [0.5 * length, 0.0]])
        self._set_outline(ends, radius, capsule_unit_moment(length, radius))

    @property
    def length(self) -> float:
        """Length of the core segment (m); the shape reaches ``radius`` beyond its ends."""
        return self._length


class Capsule(_Rod):
    """A solid capsule: the points within ``radius`` (m) of a segment of ``length`` (m)
    along the body's x axis, centred on ``position``. Mass properties are exact (a
    rectangle and two half discs). All other keywords as in :class:`Body`.
    """

    def __init__(self, *, length: float = 1.0, radius: float = 0.25, **body: Any) -> None:
        super().__init__(**body)
        length = _checks.finite_scalar("length", length)
        radius = _checks.finite_scalar("radius", radius)
        low, high = envelope.SIZE
        _checks.within("length", length, geometry.MIN_EDGE, high, unit=" m")
        _checks.within("radius", radius, 0.5 * low, high, unit=" m")
        self._set_rod(length, radius)


def capsule_unit_moment(length: float, radius: float) -> float:
    """Moment of inertia per kg (m^2) about the centre of a capsule of ``length`` and
    ``radius``: a ``length`` x ``2 radius`` rectangle, ``A_r (L^2 + 4 r^2) / 12``, and two
    half discs, each ``pi r^4 / 4`` about its flat side's centre (half a disc's polar
    moment ``pi r^4 / 2``) moved by the parallel axes to the centre: ``I_c = I_o - A
    d^2`` about its own centroid ``d = 4 r / (3 pi)`` off the flat side, then ``+ A (L/2
    + d)^2``. With no radius, a thin rod's ``L^2 / 12``."""
    if radius == 0.0:
        return length * length / 12.0
    rect = 2.0 * radius * length
    half = 0.5 * math.pi * radius * radius
    d = 4.0 * radius / (3.0 * math.pi)
    own = math.pi * radius**4 / 4.0 - half * d * d
    moment = rect * (length * length + 4.0 * radius * radius) / 12.0
    moment += 2.0 * (own + half * (0.5 * length + d) ** 2)
    return moment / (rect + 2.0 * half)


class Segment(_Rod):
    """A fixed (or kinematic) line from ``start`` to ``end`` (m, world points when made),
    rounded by ``radius`` (m, default 0): terrain, a ramp, a wall. It is a capsule with
    its centre at the middle; it cannot be dynamic (a line has no area to give it a
    moment: give it a radius and use :class:`Capsule`).
    """

    def __init__(
        self, *, start: Any, end: Any, radius: float = 0.0, kinematic: bool = False, **body: Any
    ) -> None:
        if "fixed" in body or "position" in body or "angle" in body:
            raise ValueError(
                "a Segment is placed by start and end; leave fixed, position, angle out"
            )
        a, b = _checks.vector2("start", start), _checks.vector2("end", end)
        COORDINATE("start", a)
        COORDINATE("end", b)
        length = float(np.hypot(*(b - a)))
        if not length >= geometry.MIN_EDGE:
            raise ValueError(
                f"end must be at least {geometry.MIN_EDGE} m from start, got {length:g}"
            )
        radius = _checks.non_negative("radius", radius)
        _checks.within("radius", radius, 0.0, envelope.SIZE[1], unit=" m")
        angle = math.atan2(b[1] - a[1], b[0] - a[0])
        super().__init__(
            position=0.5 * (a + b), angle=angle, fixed=not kinematic, kinematic=kinematic, **body
        )
        self._set_rod(length, radius)
