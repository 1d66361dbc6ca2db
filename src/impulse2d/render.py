"""Render a world (or one world of a batch) into an RGB frame with numpy alone.

    from impulse2d.render import Renderer
    renderer = Renderer(width=480, height=270)           # camera fits the bodies at first use
    frame = renderer.render(world)                        # (270, 480, 3) uint8, y up
    frames = renderer.render_batch(batch, worlds=[0, 5])  # (2, 270, 480, 3)

Circles are drawn filled and anti-aliased with a stroke from the centre to the rim that
shows their rotation; boxes as rotated filled rectangles; planes as a line with their solid
side shaded; springs as zig-zags between their anchors. Optional debug overlays
(``debug=("contacts", "velocities", "sleeping", "aabbs")``) show the contact points of the
last step with their normals, velocity arrows (the distance covered in 0.2 s), sleeping
bodies dimmed, and bounding boxes.

What never moves (background, planes, fixed bodies) is drawn once into a cached layer and
copied for each frame, so a frame costs roughly one small patch per moving body.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import astuple, dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from . import _checks
from . import _raster as raster
from .core.state import (
    ANCHOR_AX,
    ANCHOR_AY,
    ANCHOR_BX,
    ANGLE,
    AWAKE,
    BOUND,
    BOX,
    CIRCLE,
    DYNAMIC,
    ENABLED,
    FIXED,
    HALF_H,
    HALF_W,
    KINEMATIC,
    LINK,
    MOUSE,
    NORMAL_X,
    NORMAL_Y,
    PLANE,
    POLYGON,
    ROUNDING,
    SPRING_ON,
    VERTEX0,
    VERTEX_COUNT,
    VX,
    VY,
    X,
    Y,
)

if TYPE_CHECKING:
    from .world import World

RGB = tuple[int, int, int]
DEBUG_OVERLAYS = ("contacts", "velocities", "sleeping", "aabbs")


@dataclass
class Camera:
    """Maps world metres to pixels: ``center`` (m) lands in the middle of the frame, and one
    metre is ``pixels_per_metre`` pixels. The world's y axis points up on screen."""

    center: tuple[float, float] = (0.0, 0.0)
    pixels_per_metre: float = 50.0

    def __post_init__(self) -> None:
        self.center = tuple(_checks.vector2("center", self.center).tolist())
        self.pixels_per_metre = _checks.positive("pixels_per_metre", self.pixels_per_metre)

    @classmethod
    def fit_view(cls, view: Any, width: int, height: int) -> Camera:
        """The camera that shows the rectangle ``view = (xmin, ymin, xmax, ymax)`` (m)
        whole, centred, keeping the aspect ratio."""
        xmin, ymin, xmax, ymax = _checks.real_array("view", view, (4,)).tolist()
        if xmax <= xmin or ymax <= ymin:
            raise ValueError(f"view must have xmax > xmin and ymax > ymin, got {view!r}")
        scale = min(width / (xmax - xmin), height / (ymax - ymin))
        return cls(((xmin + xmax) / 2, (ymin + ymax) / 2), scale)

    @classmethod
    def fit(
        cls, world: World, width: int, height: int, margin: float = 0.08, world_index: int = 0
    ) -> Camera:
        """The camera that shows every enabled circle and box of one world, with a margin
        (a fraction of the frame) around them. Planes are infinite and not fitted."""
        view = _WorldView(world, world_index)
        shown = view.slots(moving=True)
        shown = np.concatenate([shown, view.slots(moving=False)])
        if not shown.size:
            return cls.fit_view((-5.0, -5.0, 5.0, 5.0), width, height)
        reach = world.state.body[world_index, shown, BOUND]
        x, y = view.x[shown], view.y[shown]
        xmin, xmax = float((x - reach).min()), float((x + reach).max())
        ymin, ymax = float((y - reach).min()), float((y + reach).max())
        pad = margin * max(xmax - xmin, ymax - ymin, 1e-3)
        return cls.fit_view((xmin - pad, ymin - pad, xmax + pad, ymax + pad), width, height)

    def to_pixels(self, x: Any, y: Any, width: int, height: int) -> tuple[Any, Any]:
        """Pixel coordinates (x right, y down) of world points."""
        s = self.pixels_per_metre
        return (np.asarray(x) - self.center[0]) * s + 0.5 * width, 0.5 * height - (
            np.asarray(y) - self.center[1]
        ) * s


@dataclass
class Style:
    """Colours (RGB, 0-255). Bodies are coloured by kind and motion type unless
    ``body_colours`` maps their slot (``body.slot``) to a colour of their own."""

    background: RGB = (24, 26, 33)
    circle: RGB = (88, 166, 255)
    box: RGB = (255, 170, 90)
    fixed: RGB = (132, 138, 150)
    kinematic: RGB = (178, 130, 255)
    plane_fill: RGB = (52, 56, 66)
    plane_line: RGB = (190, 194, 204)
    spring: RGB = (225, 225, 225)
    contact: RGB = (255, 80, 80)
    normal: RGB = (255, 215, 70)
    velocity: RGB = (110, 240, 140)
    aabb: RGB = (235, 235, 235)
    sleeping_dim: float = 0.45
    body_colours: dict[int, RGB] = field(default_factory=dict)

    def colour_of(self, slot: int, kind: int, motion: int) -> np.ndarray:
        if slot in self.body_colours:
            return np.asarray(self.body_colours[slot], np.float32)
        if motion == FIXED:
            return np.asarray(self.fixed, np.float32)
        if motion == KINEMATIC:
            return np.asarray(self.kinematic, np.float32)
        return np.asarray(self.circle if kind == CIRCLE else self.box, np.float32)


class Renderer:
    """Draws worlds into ``(height, width, 3)`` uint8 frames (see the module docstring).

    ``camera`` None fits the bodies of the first world rendered and then stays put, so a
    video does not wobble; set ``renderer.camera`` to move it.
    """

    def __init__(
        self,
        width: int = 480,
        height: int = 270,
        camera: Camera | None = None,
        style: Style | None = None,
        debug: Any = (),
        underlay: Callable[[np.ndarray, Renderer], None] | None = None,
        overlay: Callable[[np.ndarray, Renderer, int], None] | None = None,
    ) -> None:
        self.width = _checks.positive_int("width", width)
        self.height = _checks.positive_int("height", height)
        if camera is not None and not isinstance(camera, Camera):
            raise ValueError(f"camera must be a Camera or None, got {type(camera).__name__}")
        self.camera = camera
        self.style = style if style is not None else Style()
        debug = (debug,) if isinstance(debug, str) else tuple(debug)
        for name in debug:
            _checks.choice("debug", name, DEBUG_OVERLAYS)
        self.debug = frozenset(debug)
        # Game decorations: ``underlay(canvas, renderer)`` paints scenery that never changes
        # (a table's cloth and pockets) under the bodies, once; ``overlay(canvas, renderer,
        # world_index)`` paints over each frame (health bars, an aim line).
        self.underlay, self.overlay = underlay, overlay
        self._static_key: Any = None
        self._static: np.ndarray | None = None

    # -- public ------------------------------------------------------------------------------
    def render(self, world: World, world_index: int = 0) -> np.ndarray:
        """One frame of world ``world_index`` of the batch."""
        if not 0 <= world_index < world.batch_size:
            raise ValueError(f"world_index must be in [0, {world.batch_size}), got {world_index}")
        if self.camera is None:
            self.camera = Camera.fit(world, self.width, self.height, world_index=world_index)
        view = _WorldView(world, world_index)
        canvas = self._static_layer(view).copy()
        self._draw_bodies(canvas, view, moving=True)
        self._draw_springs(canvas, world, world_index)
        if "contacts" in self.debug:
            self._draw_contacts(canvas, world, world_index)
        if "velocities" in self.debug:
            self._draw_velocities(canvas, view)
        if "aabbs" in self.debug:
            self._draw_aabbs(canvas, view)
        if self.overlay is not None:
            self.overlay(canvas, self, world_index)
        return (canvas + 0.5).astype(np.uint8)

    def render_batch(self, world: World, worlds: Any = None) -> np.ndarray:
        """Frames of several worlds of a batch, shape ``(len(worlds), height, width, 3)``."""
        indices = range(world.batch_size) if worlds is None else [int(i) for i in worlds]
        return np.stack([self.render(world, i) for i in indices])

    # -- layers ------------------------------------------------------------------------------
    def _static_layer(self, view: _WorldView) -> np.ndarray:
        """Background, planes and fixed bodies, redrawn only when one of them changes."""
        fixed = view.slots(moving=False)
        key = (
            self.width,
            self.height,
            self.camera.center,
            self.camera.pixels_per_metre,
            astuple(self.style)[:-1],
            tuple(sorted(self.style.body_colours.items())),
            self.debug,
            self.underlay,
            view.signature(fixed),
        )
        if key != self._static_key:
            canvas = np.empty((self.height, self.width, 3), np.float32)
            canvas[...] = np.asarray(self.style.background, np.float32)
            if self.underlay is not None:
                self.underlay(canvas, self)
            for slot in view.planes():
                self._draw_plane(canvas, view, slot)
            self._draw_bodies(canvas, view, moving=False)
            self._static, self._static_key = canvas, key
        return self._static

    def to_pixels(self, x: float, y: float) -> tuple[float, float]:
        """Pixel coordinates (x right, y down) of a world point, with this renderer's
        camera (for decorations)."""
        return self._px(x, y)

    def to_world(self, px: float, py: float) -> np.ndarray:
        """The world point (m) drawn at pixel ``(px, py)``: the inverse of ``to_pixels``
        (for mouse input)."""
        s = self.camera.pixels_per_metre
        return np.array(
            [
                (px - 0.5 * self.width) / s + self.camera.center[0],
                (0.5 * self.height - py) / s + self.camera.center[1],
            ]
        )

    def _px(self, x: float, y: float) -> tuple[float, float]:
        s = self.camera.pixels_per_metre
        return (
            (x - self.camera.center[0]) * s + 0.5 * self.width,
            0.5 * self.height - (y - self.camera.center[1]) * s,
        )

    def _draw_plane(self, canvas: np.ndarray, view: _WorldView, slot: int) -> None:
        px, py = self._px(view.x[slot], view.y[slot])
        nx, ny = float(view.normal_x[slot]), -float(view.normal_y[slot])  # screen y is down
        colour = (
            self.style.colour_of(slot, PLANE, FIXED)
            if slot in self.style.body_colours
            else np.asarray(self.style.plane_line, np.float32)
        )
        raster.half_plane(
            canvas, px, py, nx, ny, np.asarray(self.style.plane_fill, np.float32), 0.85, colour, 2.0
        )

    def _draw_bodies(self, canvas: np.ndarray, view: _WorldView, moving: bool) -> None:
        s = self.camera.pixels_per_metre
        dim = "sleeping" in self.debug
        for slot in view.slots(moving):
            colour = self.style.colour_of(slot, view.kind[slot], view.motion[slot])
            if dim and view.motion[slot] == DYNAMIC and not view.awake[slot]:
                colour = colour * self.style.sleeping_dim
            cx, cy = self._px(view.x[slot], view.y[slot])
            angle = float(view.angle[slot])
            if view.kind[slot] == CIRCLE:
                radius = float(view.half_w[slot]) * s
                raster.disc(canvas, cx, cy, radius, colour)
                # The rotation mark: a stroke from the centre to the rim at the body's angle.
                mark, width = colour * 0.35, max(1.0, 0.15 * radius)
                reach = max(radius - 0.5 * width, 0.0)  # the round cap stays inside the disc
                tip_x, tip_y = cx + reach * math.cos(angle), cy - reach * math.sin(angle)
                raster.segment(canvas, cx, cy, tip_x, tip_y, width, mark)
            elif view.kind[slot] == POLYGON:
                corners = view.world_vertices(slot)
                points = np.column_stack(self._px(corners[:, 0], corners[:, 1]))
                raster.polygon(canvas, points, float(view.hull[slot, ROUNDING]) * s, colour)
            else:
                raster.box(
                    canvas,
                    cx,
                    cy,
                    angle,
                    float(view.half_w[slot]) * s,
                    float(view.half_h[slot]) * s,
                    colour,
                )

    def _draw_springs(self, canvas: np.ndarray, world: World, index: int) -> None:
        colour = np.asarray(self.style.spring, np.float32)
        for spring in world.springs:
            if not bool(
                np.atleast_1d(spring.body1.enabled)[index]
                and np.atleast_1d(spring.body2.enabled)[index]
            ):
                continue
            a = np.atleast_2d(spring.body1.to_world(spring.anchor1))[
                index if world.batch_size > 1 else 0
            ]
            b = np.atleast_2d(spring.body2.to_world(spring.anchor2))[
                index if world.batch_size > 1 else 0
            ]
            x0, y0 = self._px(float(a[0]), float(a[1]))
            x1, y1 = self._px(float(b[0]), float(b[1]))
            _zigzag(canvas, x0, y0, x1, y1, colour)
        self._draw_joints(canvas, world, index, colour)

    def _draw_joints(self, canvas: np.ndarray, world: World, index: int, colour: Any) -> None:
        """Each joint that acts: a line from each body's centre to its anchor, and a dot
        on the anchors (a mouse joint: its line to the target)."""
        state = world.state
        for joint in world.joints:
            row = state.spring[index, joint.slot]
            if row[SPRING_ON] != 1.0:
                continue
            ends = []
            for body, column in ((joint.body1, ANCHOR_AX), (joint.body2, ANCHOR_BX)):
                body_row = state.body[index, body.slot]
                c, s = math.cos(body_row[ANGLE]), math.sin(body_row[ANGLE])
                lx, ly = row[column], row[column + 1]
                anchor = (body_row[X] + c * lx - s * ly, body_row[Y] + s * lx + c * ly)
                ends.append((self._px(body_row[X], body_row[Y]), self._px(*anchor)))
            if row[LINK] == MOUSE:
                target = self._px(row[ANCHOR_AX], row[ANCHOR_AY])
                raster.segment(canvas, *ends[1][1], *target, 1.5, colour)
                continue
            for centre, anchor in ends:
                raster.segment(canvas, *centre, *anchor, 1.5, colour)
            for _, anchor in ends:
                raster.disc(canvas, *anchor, 2.5, colour)

    def _draw_contacts(self, canvas: np.ndarray, world: World, index: int) -> None:
        contacts = world.contacts(index)
        if contacts.size == 0:
            return
        x, y = contacts.point[:, 0], contacts.point[:, 1]
        nx, ny = contacts.normal[:, 0], contacts.normal[:, 1]
        dot, line = (
            np.asarray(self.style.contact, np.float32),
            np.asarray(self.style.normal, np.float32),
        )
        for i in range(contacts.size):
            px, py = self._px(float(x[i]), float(y[i]))
            raster.segment(
                canvas, px, py, px + 12.0 * float(nx[i]), py - 12.0 * float(ny[i]), 1.5, line
            )
            raster.disc(canvas, px, py, 2.5, dot)

    def _draw_velocities(self, canvas: np.ndarray, view: _WorldView) -> None:
        colour = np.asarray(self.style.velocity, np.float32)
        seconds = 0.2  # an arrow shows the distance covered in this time
        for slot in view.slots(moving=True):
            vx, vy = float(view.vx[slot]), float(view.vy[slot])
            if vx == 0.0 and vy == 0.0:
                continue
            x0, y0 = self._px(view.x[slot], view.y[slot])
            x1, y1 = self._px(view.x[slot] + seconds * vx, view.y[slot] + seconds * vy)
            raster.arrow(canvas, x0, y0, x1, y1, 1.5, colour)

    def _draw_aabbs(self, canvas: np.ndarray, view: _WorldView) -> None:
        colour = np.asarray(self.style.aabb, np.float32)
        for slot in np.concatenate([view.slots(moving=True), view.slots(moving=False)]):
            c, s = abs(math.cos(view.angle[slot])), abs(math.sin(view.angle[slot]))
            hw, hh = float(view.half_w[slot]), float(view.half_h[slot])
            ex, ey = (hw, hw) if view.kind[slot] == CIRCLE else (c * hw + s * hh, s * hw + c * hh)
            if view.kind[slot] == POLYGON:
                corners = view.world_vertices(slot) - [view.x[slot], view.y[slot]]
                ex, ey = np.abs(corners).max(axis=0) + view.hull[slot, ROUNDING]
            x0, y0 = self._px(view.x[slot] - ex, view.y[slot] + ey)
            x1, y1 = self._px(view.x[slot] + ex, view.y[slot] - ey)
            raster.rectangle_outline(canvas, x0, y0, x1, y1, 1.0, colour, 0.8)


class _WorldView:
    """The arrays of one world of a batch that drawing needs, as plain per-slot arrays."""

    def __init__(self, world: World, index: int) -> None:
        body, body_i = world.state.body[index], world.state.body_i[index]
        self.kind, self.motion = world.layout.kind, world.layout.motion
        self.enabled, self.awake = body_i[:, ENABLED] == 1, body_i[:, AWAKE] == 1
        self.x, self.y, self.angle = body[:, X], body[:, Y], body[:, ANGLE]
        self.vx, self.vy = body[:, VX], body[:, VY]
        self.half_w, self.half_h = body[:, HALF_W], body[:, HALF_H]
        self.normal_x, self.normal_y = body[:, NORMAL_X], body[:, NORMAL_Y]
        self.hull = world.state.hull[index]

    def world_vertices(self, slot: int) -> np.ndarray:
        """A polygon's vertices (n, 2) in world coordinates (m)."""
        row = self.hull[slot]
        n = int(row[VERTEX_COUNT])
        local = row[VERTEX0 : VERTEX0 + 2 * n].reshape(n, 2)
        c, s = math.cos(self.angle[slot]), math.sin(self.angle[slot])
        return local @ np.array([[c, s], [-s, c]]) + [self.x[slot], self.y[slot]]

    def slots(self, moving: bool) -> np.ndarray:
        """Enabled circles, boxes and polygons that can move (or that are fixed), in slot
        order."""
        solid = ((self.kind == CIRCLE) | (self.kind == BOX) | (self.kind == POLYGON)) & self.enabled
        fixed = self.motion == FIXED
        return np.flatnonzero(solid & (~fixed if moving else fixed))

    def planes(self) -> np.ndarray:
        return np.flatnonzero((self.kind == PLANE) & self.enabled)

    def signature(self, fixed: np.ndarray) -> bytes:
        """Everything about the scenery that changes its picture."""
        planes = self.planes()
        parts = [fixed, planes]
        for array in (self.x, self.y, self.angle, self.half_w, self.half_h):
            parts.append(array[fixed])
        if self.hull.shape[0] == len(self.kind):  # polygons are about: a row a slot
            parts.append(self.hull[fixed])
        for array in (self.x, self.y, self.normal_x, self.normal_y):
            parts.append(array[planes])
        return b"".join(np.ascontiguousarray(p).tobytes() for p in parts)


def _zigzag(
    canvas: np.ndarray,
    x0: float,
    y0: float,
    x1: float,
    y1: float,
    colour: np.ndarray,
    teeth: int = 8,
    amplitude: float = 4.0,
) -> None:
    """A spring drawn as a zig-zag between two screen points."""
    length = math.hypot(x1 - x0, y1 - y0)
    if length < 1e-6:
        return
    ux, uy = (x1 - x0) / length, (y1 - y0) / length
    points = [(x0, y0)]
    for k in range(1, 2 * teeth):
        t = k / (2 * teeth)
        side = amplitude if k % 2 else -amplitude
        points.append((x0 + t * (x1 - x0) - side * uy, y0 + t * (y1 - y0) + side * ux))
    points.append((x1, y1))
    for (a, b), (c, d) in itertools.pairwise(points):
        raster.segment(canvas, a, b, c, d, 1.5, colour)
