"""Anti-aliased 2D primitives drawn with numpy into a float32 RGB canvas.

Every shape is drawn from its signed distance field: for each pixel centre in the shape's
bounding box, ``d`` is the distance to the shape's edge in pixels (negative inside), and
the pixel's coverage is ``clip(0.5 - d, 0, 1)``: 1 well inside, 0 well outside, and a
one-pixel ramp across the edge, which is what anti-aliasing a filled shape amounts to.
The colour is then blended in: ``canvas += coverage * alpha * (colour - canvas)``.

Coordinates here are pixels, x to the right and y *down*; ``render.py`` converts from
world metres. Pixel ``(row i, column j)`` has its centre at ``(j + 0.5, i + 0.5)``.
"""

from __future__ import annotations

import math

import numpy as np

Colour = np.ndarray  # float32 (3,), 0..255


def _window(canvas: np.ndarray, x0: float, y0: float, x1: float, y1: float):
    """The integer pixel window covering [x0, x1] x [y0, y1], clipped to the canvas, and the
    pixel-centre coordinates along each axis (or None when it is off the canvas)."""
    height, width = canvas.shape[:2]
    j0, j1 = max(math.floor(x0), 0), min(math.ceil(x1) + 1, width)
    i0, i1 = max(math.floor(y0), 0), min(math.ceil(y1) + 1, height)
    if j0 >= j1 or i0 >= i1:
        return None
    xs = np.arange(j0, j1, dtype=np.float32) + 0.5
    ys = np.arange(i0, i1, dtype=np.float32) + 0.5
    return i0, i1, j0, j1, xs, ys


def _blend(
    canvas: np.ndarray,
    i0: int,
    i1: int,
    j0: int,
    j1: int,
    coverage: np.ndarray,
    colour: Colour,
    alpha: float = 1.0,
) -> None:
    if alpha != 1.0:
        coverage = coverage * alpha
    region = canvas[i0:i1, j0:j1]
    region += coverage[..., None] * (colour - region)


def disc(
    canvas: np.ndarray, cx: float, cy: float, radius: float, colour: Colour, alpha: float = 1.0
) -> None:
    """A filled disc of ``radius`` pixels centred at ``(cx, cy)``."""
    window = _window(canvas, cx - radius - 1, cy - radius - 1, cx + radius + 1, cy + radius + 1)
    if window is None:
        return
    i0, i1, j0, j1, xs, ys = window
    dx, dy = xs - cx, ys - cy
    distance = np.sqrt(dy[:, None] ** 2 + dx[None, :] ** 2) - radius
    _blend(canvas, i0, i1, j0, j1, np.clip(0.5 - distance, 0.0, 1.0), colour, alpha)


def box(
    canvas: np.ndarray,
    cx: float,
    cy: float,
    angle: float,
    half_w: float,
    half_h: float,
    colour: Colour,
    alpha: float = 1.0,
) -> None:
    """A filled rectangle of half sizes ``half_w`` x ``half_h`` pixels centred at
    ``(cx, cy)``, turned counter-clockwise by ``angle`` as seen on screen (y up)."""
    c, s = math.cos(angle), math.sin(angle)
    ex, ey = abs(c) * half_w + abs(s) * half_h, abs(s) * half_w + abs(c) * half_h
    window = _window(canvas, cx - ex - 1, cy - ey - 1, cx + ex + 1, cy + ey + 1)
    if window is None:
        return
    i0, i1, j0, j1, xs, ys = window
    dx = (xs - cx)[None, :]
    up = (cy - ys)[:, None]  # screen y is down; the box's frame has y up
    local_x = np.abs(c * dx + s * up) - half_w
    local_y = np.abs(-s * dx + c * up) - half_h
    outside = np.sqrt(np.maximum(local_x, 0.0) ** 2 + np.maximum(local_y, 0.0) ** 2)
    distance = outside + np.minimum(np.maximum(local_x, local_y), 0.0)
    _blend(canvas, i0, i1, j0, j1, np.clip(0.5 - distance, 0.0, 1.0), colour, alpha)


def polygon(
    canvas: np.ndarray, points: np.ndarray, radius: float, colour: Colour, alpha: float = 1.0
) -> None:
    """A filled convex polygon with corners ``points`` (n, 2) in pixels (counter-clockwise
    as the world sees it, so clockwise on screen; n >= 2), rounded by ``radius`` pixels.
    Its signed distance: inside, the largest of the edges' signed distances (each <= 0);
    outside, the distance to the nearest edge segment; minus the rounding."""
    points = np.asarray(points, np.float64)
    low, high = points.min(axis=0) - radius - 1, points.max(axis=0) + radius + 1
    window = _window(canvas, low[0], low[1], high[0], high[1])
    if window is None:
        return
    i0, i1, j0, j1, xs, ys = window
    p = np.stack(np.meshgrid(xs, ys), axis=-1)[..., None, :]  # (h, w, 1, 2)
    start = points
    edge = np.roll(points, -1, axis=0) - points
    # Clockwise on screen (y down): the outward normal of edge e is (-e_y, e_x).
    normal = np.column_stack([-edge[:, 1], edge[:, 0]]) / np.hypot(edge[:, 0], edge[:, 1])[:, None]
    gaps = np.sum((p - start) * normal, axis=-1).max(axis=-1)
    t = np.clip(np.sum((p - start) * edge, axis=-1) / np.sum(edge * edge, axis=-1), 0.0, 1.0)
    nearest = np.linalg.norm(p - start - t[..., None] * edge, axis=-1).min(axis=-1)
    inside = gaps <= 0.0 if len(points) > 2 else np.zeros(gaps.shape, bool)
    distance = np.where(inside, gaps, nearest) - radius
    _blend(canvas, i0, i1, j0, j1, np.clip(0.5 - distance, 0.0, 1.0), colour, alpha)


def segment(
    canvas: np.ndarray,
    x0: float,
    y0: float,
    x1: float,
    y1: float,
    width: float,
    colour: Colour,
    alpha: float = 1.0,
) -> None:
    """A line ``width`` pixels wide from ``(x0, y0)`` to ``(x1, y1)``, with round ends."""
    half = 0.5 * width
    window = _window(
        canvas,
        min(x0, x1) - half - 1,
        min(y0, y1) - half - 1,
        max(x0, x1) + half + 1,
        max(y0, y1) + half + 1,
    )
    if window is None:
        return
    i0, i1, j0, j1, xs, ys = window
    vx, vy = x1 - x0, y1 - y0
    length2 = vx * vx + vy * vy
    px, py = (xs - x0)[None, :], (ys - y0)[:, None]
    t = np.clip((px * vx + py * vy) / length2, 0.0, 1.0) if length2 > 0 else 0.0
    distance = np.sqrt((px - t * vx) ** 2 + (py - t * vy) ** 2) - half
    _blend(canvas, i0, i1, j0, j1, np.clip(0.5 - distance, 0.0, 1.0), colour, alpha)


def half_plane(
    canvas: np.ndarray,
    px: float,
    py: float,
    nx: float,
    ny: float,
    fill: Colour,
    fill_alpha: float,
    line: Colour,
    line_width: float,
) -> None:
    """The solid side of a plane through ``(px, py)`` with screen normal ``(nx, ny)``
    (unit, pointing out of the solid): shaded, with an anti-aliased line on its edge."""
    height, width = canvas.shape[:2]
    xs = np.arange(width, dtype=np.float32) + 0.5 - px
    ys = np.arange(height, dtype=np.float32) + 0.5 - py
    distance = xs[None, :] * nx + ys[:, None] * ny  # > 0 outside (in front of the plane)
    _blend(canvas, 0, height, 0, width, np.clip(0.5 - distance, 0.0, 1.0), fill, fill_alpha)
    band = np.clip(0.5 * line_width + 0.5 - np.abs(distance), 0.0, 1.0)
    _blend(canvas, 0, height, 0, width, band, line)


def rectangle_outline(
    canvas: np.ndarray,
    x0: float,
    y0: float,
    x1: float,
    y1: float,
    width: float,
    colour: Colour,
    alpha: float = 1.0,
) -> None:
    """The outline of an axis-aligned rectangle (for bounding boxes)."""
    for a, b, c, d in ((x0, y0, x1, y0), (x1, y0, x1, y1), (x1, y1, x0, y1), (x0, y1, x0, y0)):
        segment(canvas, a, b, c, d, width, colour, alpha)


def arrow(
    canvas: np.ndarray, x0: float, y0: float, x1: float, y1: float, width: float, colour: Colour
) -> None:
    """A line with a two-stroke head at ``(x1, y1)``."""
    segment(canvas, x0, y0, x1, y1, width, colour)
    length = math.hypot(x1 - x0, y1 - y0)
    if length < 1e-6:
        return
    head = min(6.0 + width, 0.4 * length)
    ux, uy = (x1 - x0) / length, (y1 - y0) / length
    for side in (1.0, -1.0):
        # Each stroke turned 30 degrees back from the line.
        hx = -ux * 0.866 - side * uy * 0.5
        hy = -uy * 0.866 + side * ux * 0.5
        segment(canvas, x1, y1, x1 + head * hx, y1 + head * hy, width, colour)
