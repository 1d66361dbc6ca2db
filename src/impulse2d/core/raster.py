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
from .state import CIRCLE, COS, ENABLED, FREE, HALF_H, HALF_W, PLANE, SIN, X, Y


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


@kernel
def draw(frames, background, body, body_i, shapes, colours, scale, left, top, first, last):
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
            else:
                box(frame, cx, cy, half_w, half_h, body[w, slot, COS], body[w, slot, SIN],
                    palette[slot])  # fmt: skip
