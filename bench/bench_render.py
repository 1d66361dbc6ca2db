"""Rendering speed: frames per second of impulse2d's numpy rasteriser.

Scenes: the 16-ball pool table (four cushions, balls spread after the break) and the
10-row pyramid of 55 boxes on a ground, each at 480 x 270 and 960 x 540, without and with
the debug overlays (contacts, velocities, AABBs). The world is stepped between frames, as
when recording an episode, but only the rendering is timed. Target: 200 frames/s for the
pool table at 480 x 270.

For scale, the same frame drawn with pygame-ce (C, SDL) when it is installed: filled
circles and rotated polygons, no anti-aliasing, into an off-screen surface, then copied
out to a numpy array as a renderer for RL must.

Run: ``python bench/bench_render.py``.
"""

from __future__ import annotations

import time

import numpy as np

import impulse2d as p2
from impulse2d.render import Renderer

try:
    from bench.bench_engine import _pool_world, _pyramid_world
    from bench.scenes import pool_break, pyramid
except ImportError:
    from bench_engine import _pool_world, _pyramid_world
    from scenes import pool_break, pyramid

SIZES = ((480, 270), (960, 540))
FRAMES = 200


def pool_world() -> p2.World:
    """The benchmark pool break, stepped 90 steps so the balls are spread out."""
    scene = pool_break()
    world, _, _ = _pool_world(scene, substeps=2, sleeping=True)
    for _ in range(90):
        world.step(scene.dt)
    return world


def pyramid_world() -> p2.World:
    """The 10-row pyramid of 55 unit boxes on a fixed ground box, settled for 1 s."""
    scene = pyramid(10)
    world, _ = _pyramid_world(scene)
    for _ in range(60):
        world.step(scene.dt)
    return world


def frames_per_second(
    world: p2.World, width: int, height: int, view: tuple, debug: tuple, dt: float
) -> float:
    """Median-free simple figure: FRAMES frames, the world stepped between them."""
    renderer = Renderer(
        width, height, camera=p2.render.Camera.fit_view(view, width, height), debug=debug
    )
    renderer.render(world)  # draws the cached scenery layer
    spent = 0.0
    for _ in range(FRAMES):
        world.step(dt)
        began = time.perf_counter()
        renderer.render(world)
        spent += time.perf_counter() - began
    return FRAMES / spent


def pygame_frames_per_second(world: p2.World, width: int, height: int, view: tuple) -> float:
    """The same frame with pygame-ce's C drawing (no anti-aliasing), copied to numpy."""
    import os

    os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
    import pygame

    camera = p2.render.Camera.fit_view(view, width, height)
    surface = pygame.Surface((width, height))
    bodies = world.bodies
    began = time.perf_counter()
    for _ in range(FRAMES):
        surface.fill((24, 26, 33))
        for body in bodies:
            x, y = camera.to_pixels(*body.position, width, height)
            s = camera.pixels_per_metre
            if isinstance(body, p2.Circle):
                pygame.draw.circle(surface, (88, 166, 255), (float(x), float(y)), body.radius * s)
            elif isinstance(body, p2.Box):
                c, sn = np.cos(body.angle), np.sin(body.angle)
                hw, hh = body.width * s / 2, body.height * s / 2
                corners = [
                    (float(x + c * a - sn * b), float(y - (sn * a + c * b)))
                    for a, b in ((hw, hh), (-hw, hh), (-hw, -hh), (hw, -hh))
                ]
                pygame.draw.polygon(surface, (255, 170, 90), corners)
        pygame.surfarray.array3d(surface)
    return FRAMES / (time.perf_counter() - began)


def main() -> None:
    scenes = {
        "pool table (16 balls, 4 cushions)": (pool_world, (-1.45, -0.8, 1.45, 0.8), 1 / 120),
        "pyramid (55 boxes)": (pyramid_world, (-7.0, -1.0, 7.0, 11.0), 1 / 60),
    }
    try:
        import pygame  # noqa: F401

        has_pygame = True
    except ImportError:
        has_pygame = False
    print(
        f"impulse2d numpy rasteriser, frames/s over {FRAMES} frames (world stepped between "
        "frames, only rendering timed); target: pool table at 480 x 270 >= 200"
    )
    header = f"{'scene':36s} {'size':>9s} {'plain':>8s} {'debug':>8s}"
    print(header + (f" {'pygame-ce':>10s} {'ratio':>6s}" if has_pygame else ""))
    for name, (build, view, dt) in scenes.items():
        for width, height in SIZES:
            plain = frames_per_second(build(), width, height, view, (), dt)
            debug = frames_per_second(
                build(), width, height, view, ("contacts", "velocities", "aabbs"), dt
            )
            line = f"{name:36s} {width:4d}x{height:<4d} {plain:8.0f} {debug:8.0f}"
            if has_pygame:
                peer = pygame_frames_per_second(build(), width, height, view)
                line += f" {peer:10.0f} {plain / peer:6.2f}"
            print(line)


if __name__ == "__main__":
    main()
