"""A pygame-ce window that shows frames at a fixed rate (``render_mode="human"``).

pygame-ce is the optional extra ``impulse2d[play]``; without it, or without a display,
the error says what to install or to use ``render_mode="rgb_array"`` instead.
"""

from __future__ import annotations

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


class Window:
    """Shows ``(height, width, 3)`` frames, at most ``fps`` per second."""

    def __init__(self, width: int, height: int, fps: float, title: str = "impulse2d") -> None:
        pygame = self.pygame = load_pygame()
        pygame.display.init()
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
