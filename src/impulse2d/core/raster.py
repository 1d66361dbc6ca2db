"""Frames of many worlds at once, compiled: the bodies of each world drawn into its frame.

For agents that learn from pixels a frame is an observation, made for every world of a
batch at every step, so it is drawn here by the same compiler as the step, world by
world (``draw`` takes a range of worlds; ``pixels.Frames`` hands the ranges to threads).
What does not move is drawn once by the caller into ``background``, which every frame
starts from.

A shape is drawn from its signed distance field, as ``impulse2d._raster`` draws with
numpy: for each pixel centre near the shape, ``d`` is the distance to the shape's edge in
pixels (negative inside) and the pixel's coverage is ``clip(0.5 - d, 0, 1)``, a one-pixel
ramp across the edge (anti-aliasing, which keeps a ball of two pixels a ball as it moves
by fractions of one); the body's colour is blended in by it,
``v + coverage (colour - v)``, rounded to the nearest of 0..255.

Pixels: row ``i`` and column ``j`` have their centre at ``(j + 0.5, i + 0.5)``, x to the
right and y down; a world point ``(x, y)`` is at ``((x - left) scale, (top - y) scale)``.
"""

from __future__ import annotations

import math

from ._jit import inline, kernel
from .state import (
    CIRCLE,
    COS,
    EDGE_NORMAL0,
    ENABLED,
    FREE,
    HALF_H,
    HALF_W,
    PLANE,
    POLYGON,
    ROUNDING,
    SIN,
    VERTEX0,
    VERTEX_COUNT,
    X,
    Y,
)


@inline
def _blend(frame, i, j, coverage, colour) -> None:
    for c in range(3):
        old = float(frame[i, j, c])
        frame[i, j, c] = int(old + coverage * (colour[c] - old) + 0.5)


@inline
def _span(centre: float, reach: float, size: int) -> tuple[int, int]:
    """The pixel indices whose centres lie within ``reach`` (+1) of ``centre``, clipped."""
    return max(math.floor(centre - reach - 1.0), 0), min(math.ceil(centre + reach + 1.0), size)


@inline
def disc(frame, cx, cy, radius, colour) -> None:
    """A filled disc of ``radius`` pixels centred at pixel ``(cx, cy)``."""
    i0, i1 = _span(cy, radius, frame.shape[0])
    j0, j1 = _span(cx, radius, frame.shape[1])
    for i in range(i0, i1):
        dy = i + 0.5 - cy
        for j in range(j0, j1):
            dx = j + 0.5 - cx
            coverage = min(max(0.5 - (math.sqrt(dx * dx + dy * dy) - radius), 0.0), 1.0)
            if coverage > 0.0:
                _blend(frame, i, j, coverage, colour)


@inline
def box(frame, cx, cy, half_w, half_h, cos, sin, colour) -> None:
    """A filled rectangle of half sizes ``half_w`` x ``half_h`` pixels centred at pixel
    ``(cx, cy)``, turned counter-clockwise (as the world sees it, y up) by the angle whose
    cosine and sine are given. In the box's frame a pixel is at ``(u, v)``; its distance
    to the rectangle is ``|max(q, 0)| + min(max(q_u, q_v), 0)``, ``q = (|u| - half_w,
    |v| - half_h)``."""
    reach = math.sqrt(half_w * half_w + half_h * half_h)
    i0, i1 = _span(cy, reach, frame.shape[0])
    j0, j1 = _span(cx, reach, frame.shape[1])
    for i in range(i0, i1):
        up = cy - (i + 0.5)  # the world's y is up, the frame's down
        for j in range(j0, j1):
            dx = j + 0.5 - cx
            qu = abs(cos * dx + sin * up) - half_w
            qv = abs(-sin * dx + cos * up) - half_h
            outside = math.sqrt(max(qu, 0.0) ** 2 + max(qv, 0.0) ** 2)
            distance = outside + min(max(qu, qv), 0.0)
            coverage = min(max(0.5 - distance, 0.0), 1.0)
            if coverage > 0.0:
                _blend(frame, i, j, coverage, colour)


@inline
def outline(frame, cx, cy, row, scale, cos, sin, colour) -> None:
    """A filled outline (a ``state.hull`` row, metres) centred at pixel ``(cx, cy)`` at
    ``scale`` pixels a metre, turned as ``box``. Its signed distance in the body frame:
    inside, the largest of the edges' ``n . (p - v)``; outside, the distance to the
    nearest edge segment; minus the rounding."""
    n = int(row[VERTEX_COUNT])
    reach = 0.0
    for k in range(n):
        vx, vy = row[VERTEX0 + 2 * k], row[VERTEX0 + 2 * k + 1]
        reach = max(reach, math.sqrt(vx * vx + vy * vy))
    reach = (reach + row[ROUNDING]) * scale
    i0, i1 = _span(cy, reach, frame.shape[0])
    j0, j1 = _span(cx, reach, frame.shape[1])
    for i in range(i0, i1):
        up = (cy - (i + 0.5)) / scale
        for j in range(j0, j1):
            dx = (j + 0.5 - cx) / scale
            u, v = cos * dx + sin * up, -sin * dx + cos * up
            gap, nearest = -math.inf, math.inf
            for k in range(n):
                ax, ay = row[VERTEX0 + 2 * k], row[VERTEX0 + 2 * k + 1]
                m = k + 1 if k + 1 < n else 0
                ex, ey = row[VERTEX0 + 2 * m] - ax, row[VERTEX0 + 2 * m + 1] - ay
                gap = max(gap, row[EDGE_NORMAL0 + 2 * k] * (u - ax)
                          + row[EDGE_NORMAL0 + 2 * k + 1] * (v - ay))  # fmt: skip
                t = min(max(((u - ax) * ex + (v - ay) * ey) / (ex * ex + ey * ey), 0.0), 1.0)
                ox, oy = u - ax - t * ex, v - ay - t * ey
                nearest = min(nearest, math.sqrt(ox * ox + oy * oy))
            core = gap if gap <= 0.0 and n > 2 else nearest
            coverage = min(max(0.5 - (core - row[ROUNDING]) * scale, 0.0), 1.0)
            if coverage > 0.0:
                _blend(frame, i, j, coverage, colour)


@kernel
def draw(frames, background, body, body_i, hull, shapes, colours, scale, left, top, first, last):
    """The frames of worlds ``first`` to ``last - 1`` (rows of ``frames``, (B, H, W, 3)
    uint8): each starts from ``background`` (H, W, 3) and gets every enabled body whose
    ``colours`` row says to draw it, in slot order, at ``scale`` pixels a metre with the
    world point ``(left, top)`` at the frame's top left corner. ``colours`` (1 or B, N,
    4): red, green, blue and drawn (0 or 1) of each slot, the same in every world or per
    world. Planes are the caller's to draw in the background."""
    for w in range(first, last):
        frame = frames[w]
        frame[:] = background
        palette = colours[w if colours.shape[0] > 1 else 0]
        for slot in range(shapes.shape[0]):
            kind = shapes[slot, 0]
            if kind == FREE or kind == PLANE or palette[slot, 3] == 0.0:
                continue
            if body_i[w, slot, ENABLED] == 0:
                continue
            cx = (body[w, slot, X] - left) * scale
            cy = (top - body[w, slot, Y]) * scale
            half_w, half_h = body[w, slot, HALF_W] * scale, body[w, slot, HALF_H] * scale
            if kind == CIRCLE:
                disc(frame, cx, cy, half_w, palette[slot])
            elif kind == POLYGON:
                outline(frame, cx, cy, hull[w, slot], scale, body[w, slot, COS],
                        body[w, slot, SIN], palette[slot])  # fmt: skip
            else:
                box(frame, cx, cy, half_w, half_h, body[w, slot, COS], body[w, slot, SIN],
                    palette[slot])  # fmt: skip
