"""Frames of every world of a batch at once, for agents that learn from pixels.

    from impulse2d.pixels import Frames
    frames = Frames(world, width=84, height=84, view=((-1.4, -0.8), (1.4, 0.8)))
    images = frames()                        # (B, 84, 84, 3) uint8, y up
    frames.colour(ball, (255, 255, 255))     # a body's own colour
    frames.hide(pocket_marker)               # a body left out of the frames

``view`` is the rectangle of the world (metres) that fills the frame: it is scaled to
fit and centred, so a view of another shape than the frame's leaves bands of background.
Every frame starts from ``background``: a colour, or an ``(height, width, 3)`` uint8
image of what never moves (``to_pixels`` places world points in it). Bodies are drawn in
slot order, anti-aliased, in compiled code (``impulse2d.core.raster``), the worlds
shared out over ``world.threads`` threads; planes are not drawn (draw them in the
background). ``impulse2d.render.Renderer`` draws one world with numpy for people to
look at, with springs, contacts and overlays; this draws what an agent sees, fast.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from . import _checks
from .core import raster
from .core.runner import in_chunks
from .render import Style
from .world import World

_CHUNKS_PER_THREAD = 8


class Frames:
    """Frames of ``world``'s batch (see the module docstring)."""

    def __init__(
        self,
        world: World,
        width: int = 84,
        height: int = 84,
        view: Any = ((-1.0, -1.0), (1.0, 1.0)),
        background: Any = (0, 0, 0),
    ) -> None:
        if not isinstance(world, World):
            raise ValueError(f"world must be an impulse2d World, got {world!r}")
        self.world = world
        self.width = _checks.int_in("width", width, 1, 4096)
        self.height = _checks.int_in("height", height, 1, 4096)
        corners = _checks.real_array("view", view, (2, 2))
        (x0, y0), (x1, y1) = corners
        if not (x1 > x0 and y1 > y0):
            raise ValueError(f"view must be ((left, bottom), (right, top)) with right > left "
                             f"and top > bottom, got {view!r}")  # fmt: skip
        self.scale = min(self.width / (x1 - x0), self.height / (y1 - y0))  # pixels a metre
        self.left = 0.5 * (x0 + x1) - 0.5 * self.width / self.scale
        self.top = 0.5 * (y0 + y1) + 0.5 * self.height / self.scale
        self.background = background
        # id(body): (body, its colour (4,) or (batch_size, 4): red, green, blue, drawn)
        self._own: dict[int, tuple[Any, np.ndarray]] = {}

    @property
    def background(self) -> np.ndarray:
        """What every frame starts from, ``(height, width, 3)`` uint8 (settable: a colour
        or such an image)."""
        return self._background

    @background.setter
    def background(self, value: Any) -> None:
        image = np.asarray(value)
        if image.shape == (3,):
            image = np.broadcast_to(_checks.rgb("background", value), (self.height, self.width, 3))
        elif image.shape != (self.height, self.width, 3) or image.dtype != np.uint8:
            raise ValueError(
                f"background must be an RGB colour or a ({self.height}, {self.width}, 3) uint8 "
                f"image, got shape {image.shape} and dtype {image.dtype}"
            )
        self._background = np.ascontiguousarray(image, dtype=np.uint8)

    def to_pixels(self, x: Any, y: Any) -> tuple[Any, Any]:
        """Pixel coordinates (x right, y down, pixel centres at +0.5) of world points."""
        return (np.asarray(x) - self.left) * self.scale, (self.top - np.asarray(y)) * self.scale

    def colour(self, body: Any, rgb: Any) -> None:
        """Draw ``body`` in ``rgb`` from now on: red, green, blue in [0, 255], the same in
        every world (shape (3,)) or one row per world (``(batch_size, 3)``)."""
        batch = self.world.batch_size
        colour = _checks.real_array("rgb", rgb)
        if colour.shape not in ((3,), (batch, 3)):
            want = "(3,)" if batch == 1 else f"(3,) or ({batch}, 3)"
            raise ValueError(f"rgb must have shape {want}, got shape {colour.shape}")
        if np.any((colour < 0.0) | (colour > 255.0)):
            raise ValueError(f"rgb must be numbers in [0, 255], got {rgb!r}")
        drawn = np.ones((*colour.shape[:-1], 1))
        self._check_body(body)
        self._own[id(body)] = (body, np.concatenate([colour, drawn], axis=-1))

    def hide(self, body: Any) -> None:
        """Leave ``body`` out of the frames."""
        self._check_body(body)
        self._own[id(body)] = (body, np.zeros(4))

    def __call__(self) -> np.ndarray:
        """Every world's frame, ``(batch_size, height, width, 3)`` uint8."""
        world = self.world
        state, shapes = world.state, world.layout.shapes
        colours = self._slot_colours(shapes)
        batch = state.batch_size
        frames = np.empty((batch, self.height, self.width, 3), np.uint8)

        def draw_chunk(_: int, first: int, last: int) -> None:
            raster.draw(frames, self._background, state.body, state.body_i, state.hull, shapes,
                        colours, self.scale, self.left, self.top, first, last)  # fmt: skip

        threads = min(world.threads, batch)
        chunks = 1 if threads == 1 else min(batch, _CHUNKS_PER_THREAD * threads)
        in_chunks(draw_chunk, batch, chunks, threads)
        return frames

    def _check_body(self, body: Any) -> None:
        if not any(body is kept for kept in self.world.objects["bodies"]):
            raise ValueError(f"body must be a body of this world, got {body!r}")

    def _slot_colours(self, shapes: np.ndarray) -> np.ndarray:
        """(1 or B, N, 4) red, green, blue, drawn: a body's own colour (where it is still
        in the world, in the slot it has now), else the renderer's default for its kind
        and motion; one row per world where a body has a colour per world. Built for
        every drawing: a few slots, against a frame of pixels each."""
        style = Style()
        per_world = any(own.ndim == 2 for _, own in self._own.values())
        colours = np.zeros((self.world.batch_size if per_world else 1, len(shapes), 4))
        for slot, (kind, motion) in enumerate(shapes):
            colours[:, slot, :3] = style.colour_of(slot, kind, motion)
        colours[..., 3] = 1.0
        for body, own in self._own.values():
            if body.slot >= 0:
                colours[:, body.slot] = own
        return colours
