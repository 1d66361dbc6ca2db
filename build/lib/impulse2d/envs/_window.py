"""A pygame-ce window that shows frames at a fixed rate (``render_mode="human"``).

pygame-ce is the optional extra ``impulse2d[play]``; without it the error says what to
install. Without a display ``Window`` raises a RuntimeError that names the display
variables, ``xvfb-run`` and ``render_mode="rgb_array"``; the envs turn it into a one-time
message and play on without a window (``envs/_gym.py``, ``_Frames``).
"""

from __future__ import annotations

import os
from typing import Any

import numpy as np


def load_pygame() -> Any:
    """pygame, or an ImportError that names the extra to install."""
    try:
        import pygame
    except ImportError as error:
        raise ImportError(
            "render_mode='human' needs pygame-ce: pip install 'impulse2d[play]'"
        ) from error
    return pygame


# SDL's video drivers that draw into memory: SDL falls back on them when it finds no
# display, and a window "opens" that nobody can see.
_HEADLESS_DRIVERS = ("offscreen", "dummy")


def require_display() -> Any:
    """pygame with its display started, or a RuntimeError naming the missing display
    when SDL found no real one (unless the user chose a headless driver with
    ``SDL_VIDEODRIVER``, as tests do)."""
    pygame = load_pygame()
    pygame.display.init()
    driver = pygame.display.get_driver()
    if driver in _HEADLESS_DRIVERS and os.environ.get("SDL_VIDEODRIVER", "") != driver:
        pygame.display.quit()
        found = {name: os.environ.get(name) for name in ("DISPLAY", "WAYLAND_DISPLAY")}
        raise RuntimeError(
            f"render_mode='human' needs a display, and SDL found none (it fell back on its "
            f"{driver!r} driver; DISPLAY={found['DISPLAY']!r}, "
            f"WAYLAND_DISPLAY={found['WAYLAND_DISPLAY']!r}): use render_mode='rgb_array' "
            "for frames as arrays, or run under a display (xvfb-run on a server)"
        )
    return pygame


class Window:
    """Shows ``(height, width, 3)`` frames, at most ``fps`` per second."""

    def __init__(self, width: int, height: int, fps: float, title: str = "impulse2d") -> None:
        pygame = self.pygame = require_display()
        try:
            self.screen = pygame.display.set_mode((width, height))
        except pygame.error as error:
            raise RuntimeError(
                f"cannot open a window ({error}); use render_mode='rgb_array' without a display"
            ) from error
        pygame.display.set_caption(title)
        self.clock = pygame.time.Clock()
        self.fps = fps

    def show(self, frame: np.ndarray) -> None:
        pygame = self.pygame
        pygame.event.pump()  # keeps the window responsive while an agent plays
        surface = pygame.surfarray.make_surface(np.ascontiguousarray(frame.swapaxes(0, 1)))
        self.screen.blit(surface, (0, 0))
        pygame.display.flip()
        self.clock.tick(self.fps)

    def close(self) -> None:
        self.pygame.display.quit()
