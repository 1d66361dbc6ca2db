"""A window to play with the demo scenes: ``python -m impulse2d.apps.sandbox [--scene NAME]``.

Needs the ``play`` extra (pygame-ce) and a display. Controls, as the tutorial's
application has them:

* drag with the mouse from a body and release: an impulse along the drag at the point
  where you pressed (the tutorial's cue stick; the cue is drawn while you drag). The
  impulse gives the body ``CUE_GAIN`` times the drag length in metres per second;
* drag with the right button: the body under the pointer follows it, held by a mouse
  joint (``impulse2d.MouseJoint``, Box2D's: a soft spring with a force limit) until you
  let go;
* ``P`` restarts the scene, ``Space`` pauses, ``.`` steps once while paused;
* ``Tab`` / ``Right`` next scene, ``Shift+Tab`` / ``Left`` previous, ``D`` debug overlays;
* ``Esc`` or ``Q`` quits.

The energy readout (linear and rotational kinetic, potential, elastic, total) is shown in
a corner, as the tutorial suggests, to watch energy move between its kinds.
"""

from __future__ import annotations

import argparse
import os
import sys
from typing import Any

import numpy as np

from .. import _raster as raster
from ..joints import MouseJoint
from ..render import Camera, Renderer
from .demo import SCENES, Scene, get

CUE_GAIN = 3.0  # 1/s: velocity change (m/s) per metre of drag
CUE_COLOUR = np.array((240, 240, 240), np.float32)


def _pygame() -> Any:
    try:
        import pygame
    except ImportError:  # pragma: no cover - exercised only without the extra
        raise SystemExit("the sandbox needs pygame-ce: pip install 'impulse2d[play]'") from None
    return pygame


def display_problem() -> str | None:
    """Why no window can open here (no display server and no SDL driver chosen), or None."""
    if os.environ.get("SDL_VIDEODRIVER"):
        return None
    if sys.platform.startswith("linux") and not (
        os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")
    ):
        return (
            "no display: DISPLAY and WAYLAND_DISPLAY are unset, so no window can open. Run "
            "it on a desktop, or render scenes to files headless with "
            "'python -m impulse2d.apps.demo NAME --out NAME.gif'"
        )
    return None


class Sandbox:
    """The sandbox's state and logic, separate from the event loop so tests can drive it."""

    def __init__(
        self, scene: str = "m09-circle-circle", width: int = 960, height: int = 540
    ) -> None:
        pygame = _pygame()
        self.pygame = pygame
        pygame.display.init()  # not pygame.init(): no sound, so no audio device is needed
        pygame.font.init()
        self.surface = pygame.display.set_mode((width, height))
        self.font = pygame.font.Font(None, 22)
        self.width, self.height = width, height
        self.names = list(SCENES)
        self.paused = False
        self.debug = False
        self.press: tuple[float, float] | None = None  # pixel where a drag started
        self.mouse = (0.0, 0.0)
        self.held: Any = None  # the mouse joint of a right-button drag
        self.load(scene)

    # -- scenes ------------------------------------------------------------------------------
    def load(self, name: str) -> None:
        """Build a scene afresh (also what ``P`` does)."""
        self.scene: Scene = get(name)
        self.world = self.scene.build()
        camera = None
        if self.scene.view is not None:
            camera = Camera.fit_view(self.scene.view, self.width, self.height)
        debug = ("contacts", "velocities") if self.debug else ()
        self.renderer = Renderer(self.width, self.height, camera=camera, debug=debug)
        self.renderer.render(self.world)  # fixes the camera before any click maps through it
        self.press, self.held = None, None

    def cycle(self, offset: int) -> None:
        index = (self.names.index(self.scene.name) + offset) % len(self.names)
        self.load(self.names[index])

    # -- input -------------------------------------------------------------------------------
    def world_point(self, pixel: tuple[float, float]) -> np.ndarray:
        return self.renderer.to_world(*pixel)

    def handle(self, event: Any) -> bool:
        """React to one pygame event; returns False when the user asked to quit."""
        pygame = self.pygame
        if event.type == pygame.QUIT:
            return False
        if event.type == pygame.KEYDOWN:
            shift = bool(event.mod & pygame.KMOD_SHIFT)
            if event.key in (pygame.K_ESCAPE, pygame.K_q):
                return False
            if event.key == pygame.K_p:
                self.load(self.scene.name)
            elif event.key == pygame.K_SPACE:
                self.paused = not self.paused
            elif event.key == pygame.K_PERIOD and self.paused:
                self.scene.step(self.world)
            elif event.key == pygame.K_TAB:
                self.cycle(-1 if shift else 1)
            elif event.key == pygame.K_RIGHT:
                self.cycle(1)
            elif event.key == pygame.K_LEFT:
                self.cycle(-1)
            elif event.key == pygame.K_d:
                self.debug = not self.debug
                self.renderer.debug = frozenset(("contacts", "velocities") if self.debug else ())
        elif event.type == pygame.MOUSEBUTTONDOWN and event.button == 1:
            self.press = self.mouse = tuple(map(float, event.pos))
        elif event.type == pygame.MOUSEBUTTONDOWN and event.button == 3:
            self.grab(tuple(map(float, event.pos)))
        elif event.type == pygame.MOUSEBUTTONUP and event.button == 3:
            self.release()
        elif event.type == pygame.MOUSEMOTION:
            self.mouse = tuple(map(float, event.pos))
            if self.held is not None:
                self.held.target = self.world_point(self.mouse)
        elif event.type == pygame.MOUSEBUTTONUP and event.button == 1 and self.press:
            self.mouse = tuple(map(float, event.pos))
            self.cue(self.press, self.mouse)
            self.press = None
        return True

    def cue(self, press: tuple[float, float], release: tuple[float, float]) -> Any:
        """The tutorial's cue stick: an impulse along the drag, at the pressed point, on the
        body under it. Returns that body (or None if the press hit nothing)."""
        start, end = self.world_point(press), self.world_point(release)
        bodies = self.world.query_point(start)
        if not bodies:
            return None
        body = bodies[-1]  # the one drawn on top
        if body.fixed or body.kinematic:
            return None
        body.apply_impulse(CUE_GAIN * body.mass * (end - start), point=start)
        return body

    def grab(self, pixel: tuple[float, float]) -> Any:
        """Hold the dynamic body under ``pixel`` with a mouse joint (returns it, or None)."""
        self.release()
        point = self.world_point(pixel)
        bodies = [b for b in self.world.query_point(point) if not (b.fixed or b.kinematic)]
        if not bodies:
            return None
        self.held = self.world.add(MouseJoint(bodies[-1], target=point))
        return self.held

    def release(self) -> None:
        """Let go of a held body."""
        if self.held is not None:
            self.world.remove(self.held)
            self.held = None

    # -- frames ------------------------------------------------------------------------------
    def update(self) -> None:
        if not self.paused:
            self.scene.step(self.world)

    def frame(self) -> np.ndarray:
        """The picture: the world, and the cue while dragging."""
        image = self.renderer.render(self.world)
        if self.press is not None:
            canvas = image.astype(np.float32)
            raster.segment(canvas, *self.press, *self.mouse, 3.0, CUE_COLOUR)
            image = (canvas + 0.5).astype(np.uint8)
        return image

    def draw(self) -> None:
        pygame = self.pygame
        pygame.surfarray.blit_array(self.surface, self.frame().swapaxes(0, 1))
        energy = self.world.energy()
        lines = [
            f"{self.scene.name}: {self.scene.description}",
            f"t = {self.world.time:6.2f} s   {'paused' if self.paused else ''}",
            f"kinetic {energy.kinetic_linear:8.2f} J  rotational {energy.kinetic_rotational:8.2f}"
            f" J  potential {energy.potential:8.2f} J  elastic {energy.elastic:8.2f} J"
            f"  total {energy.total:8.2f} J",
            "drag from a body: cue   right-drag: hold   P restart   Space pause   . step"
            "   Tab/arrows scene   D debug   Q quit",
        ]
        for row, text in enumerate(lines):
            label = self.font.render(text[:150], True, (235, 235, 235))
            self.surface.blit(label, (8, 6 + 20 * row))
        pygame.display.flip()

    def run(self, max_frames: int | None = None) -> None:
        """The event loop at the scene's time step (frames capped at 1 / dt)."""
        pygame = self.pygame
        clock = pygame.time.Clock()
        frames = 0
        while max_frames is None or frames < max_frames:
            if not all(self.handle(event) for event in pygame.event.get()):
                break
            self.update()
            self.draw()
            clock.tick(round(1.0 / self.scene.dt))
            frames += 1


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description="Play with the impulse2d demo scenes.")
    parser.add_argument("--scene", default="m09-circle-circle", help="scene to start with")
    parser.add_argument("--width", type=int, default=960)
    parser.add_argument("--height", type=int, default=540)
    args = parser.parse_args(argv)
    problem = display_problem()
    if problem is not None:
        raise SystemExit(problem)
    try:
        get(args.scene)
    except ValueError as error:
        parser.error(str(error))
    sandbox = Sandbox(args.scene, args.width, args.height)
    try:
        sandbox.run()
    finally:
        sandbox.pygame.quit()


if __name__ == "__main__":
    main()
