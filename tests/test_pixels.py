"""Frames of a batch for agents that learn from pixels (``impulse2d.pixels``, drawn by
``impulse2d.core.raster``): shapes against their geometry (a disc's area, a turned box's
area, centre and axis), where the view puts a body, a batch against its worlds alone and
on any number of threads, what is left out, the compiled drawing against plain Python,
and bad input."""

from __future__ import annotations

import os
import re
import subprocess
import sys

import numpy as np
import pytest

import impulse2d as p2
from impulse2d.pixels import Frames

WHITE = (255, 255, 255)


def _coverage(frame: np.ndarray) -> np.ndarray:
    """Coverage of white on black, 0..1 per pixel."""
    return frame[..., 0].astype(np.float64) / 255.0


def _moments(cover: np.ndarray) -> tuple[float, float, float, float]:
    """Area, centroid (x right, y down, pixel centres at +0.5) and the angle of the long
    axis measured counter-clockwise as the world sees it (y up)."""
    rows, cols = np.indices(cover.shape) + 0.5
    area = cover.sum()
    cx, cy = (cover * cols).sum() / area, (cover * rows).sum() / area
    dx, up = cols - cx, cy - rows
    sxx, syy, sxy = (cover * dx * dx).sum(), (cover * up * up).sum(), (cover * dx * up).sum()
    return area, cx, cy, 0.5 * np.arctan2(2 * sxy, sxx - syy)


def _alone(shape: p2.Circle | p2.Box, size: int = 100) -> tuple[np.ndarray, Frames]:
    world = p2.World()
    body = world.add(shape)
    frames = Frames(world, size, size, view=((-1.0, -1.0), (1.0, 1.0)))
    frames.colour(body, WHITE)
    return frames()[0], frames


def test_a_disc_covers_its_area_around_its_centre():
    frame, frames = _alone(p2.Circle(position=(0.2, -0.3), radius=0.25))
    assert frames.scale == 50.0
    area, cx, cy, _ = _moments(_coverage(frame))
    assert area == pytest.approx(np.pi * 12.5**2, rel=2e-3)  # radius 12.5 px
    assert (cx, cy) == pytest.approx((60.0, 65.0), abs=0.01)  # y down: below the middle


@pytest.mark.parametrize("angle", [0.0, 0.3, 1.1, -0.7])
def test_a_turned_box_covers_its_area_centre_and_axis(angle):
    frame, _ = _alone(p2.Box(position=(-0.1, 0.25), width=1.0, height=0.3, angle=angle))
    area, cx, cy, axis = _moments(_coverage(frame))
    assert area == pytest.approx(50 * 15, rel=2e-3)
    assert (cx, cy) == pytest.approx((45.0, 37.5), abs=0.01)
    assert axis == pytest.approx(angle, abs=2e-3)  # counter-clockwise, as in the world


def test_the_view_is_fitted_and_centred():
    world = p2.World()
    ball = world.add(p2.Circle(position=(2.0, 1.0), radius=0.1))
    frames = Frames(world, 80, 40, view=((0.0, 0.0), (4.0, 4.0)))  # fits the height
    assert frames.scale == 10.0
    assert frames.to_pixels(2.0, 2.0) == pytest.approx((40.0, 20.0))  # the view's centre
    frames.colour(ball, WHITE)
    _, cx, cy, _ = _moments(_coverage(frames()[0]))
    assert (cx, cy) == pytest.approx((40.0, 30.0), abs=0.01)


def _scene(batch: int = 1, threads: int = 1) -> p2.World:
    world = p2.World(gravity=(0.0, -9.81), batch_size=batch, threads=threads)
    world.add(p2.Plane(normal=(0, 1), point=(0, -1)))
    for i in range(6):
        world.add(p2.Box(position=(0.3 * i - 0.8, -0.6 + 0.25 * i), width=0.3, height=0.2,
                         angle=0.2 * i))  # fmt: skip
        world.add(p2.Circle(position=(0.8 - 0.3 * i, 0.5), radius=0.08 + 0.01 * i))
    return world


def test_a_batch_draws_each_world_as_it_would_alone_on_any_thread_count():
    lone = _scene()
    lone.step(1 / 60, steps=20)
    moved = [lone]
    for k in range(1, 4):
        other = _scene()
        other.bodies[3].velocity = (k, 2.0 * k)
        other.step(1 / 60, steps=20)
        moved.append(other)
    alone = np.concatenate([Frames(w, 64, 48)() for w in moved])
    for threads in (1, min(2, p2.World().threads)):
        batch = _scene(4, threads)
        for k in range(1, 4):
            velocity = np.array(batch.bodies[3].velocity)
            velocity[k] = (k, 2.0 * k)
            batch.bodies[3].velocity = velocity
        batch.step(1 / 60, steps=20)
        assert np.array_equal(Frames(batch, 64, 48)(), alone)


def test_hidden_switched_off_and_planes_are_not_drawn_and_the_background_is():
    world = p2.World()
    plane = world.add(p2.Plane(normal=(0, 1), point=(0, 0)))
    ball = world.add(p2.Circle(position=(0.0, 0.5), radius=0.2))
    box = world.add(p2.Box(position=(0.5, 0.5), width=0.2, height=0.2))
    image = np.full((32, 32, 3), 7, np.uint8)
    frames = Frames(world, 32, 32, background=image)
    frames.hide(ball)
    box.enabled = False
    assert np.array_equal(frames()[0], image)
    frames.colour(plane, WHITE)  # a plane is the background's to draw
    assert np.array_equal(frames()[0], image)
    box.enabled = True
    assert not np.array_equal(frames()[0], image)


_PLAIN = """
import hashlib, sys
sys.path.insert(0, sys.argv[1])
from test_pixels import _scene
from impulse2d.pixels import Frames
world = _scene(3)
world.step(1 / 60, steps=15)
print(hashlib.sha256(Frames(world, 40, 30)().tobytes()).hexdigest())
"""


def test_the_compiled_drawing_equals_plain_python():
    digests = []
    for jit in (True, False):
        env = {k: v for k, v in os.environ.items() if k != "NUMBA_DISABLE_JIT"}
        if not jit:
            env["NUMBA_DISABLE_JIT"] = "1"
        done = subprocess.run(
            [sys.executable, "-c", _PLAIN, os.path.dirname(__file__)], env=env,
            capture_output=True, text=True, timeout=600,
        )  # fmt: skip
        assert done.returncode == 0, done.stderr[-2000:]
        digests.append(done.stdout.strip())
    assert digests[0] == digests[1] and len(digests[0]) == 64


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"width": 0}, "width must be in [1, 4096], got 0"),
        ({"height": 2.5}, "height must be"),
        ({"view": ((1.0, 0.0), (0.0, 1.0))}, "view must be ((left, bottom), (right, top))"),
        ({"view": ((0.0, 0.0), (np.nan, 1.0))}, "view must be finite"),
        ({"view": (0.0, 1.0)}, "view must have shape (2, 2)"),
        ({"background": (0, 0, 300)}, "background must be three numbers in [0, 255]"),
        ({"background": np.zeros((5, 5, 3), np.uint8)}, "background must be an RGB colour"),
    ],
)
def test_bad_input_is_refused_by_name(kwargs, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        Frames(p2.World(), **kwargs)


def test_bad_colours_and_strangers_are_refused_by_name():
    world = p2.World()
    ball = world.add(p2.Circle())
    frames = Frames(world)
    with pytest.raises(ValueError, match=r"rgb must be numbers in \[0, 255\]"):
        frames.colour(ball, (-1, 0, 0))
    with pytest.raises(ValueError, match="rgb must have shape"):
        frames.colour(ball, (1, 2))
    with pytest.raises(ValueError, match="world must be an impulse2d World"):
        Frames("world")
    with pytest.raises(ValueError, match="body must be a body of this world"):
        frames.hide(p2.World().add(p2.Circle()))


def test_a_body_can_have_a_colour_per_world():
    world = p2.World(batch_size=2)
    ball = world.add(p2.Circle(position=(0.0, 0.0), radius=0.3))
    frames = Frames(world, 20, 20)
    frames.colour(ball, [(255, 0, 0), (0, 0, 255)])
    middle = frames()[:, 10, 10]
    assert middle.tolist() == [[255, 0, 0], [0, 0, 255]]
    with pytest.raises(ValueError, match=r"rgb must have shape \(3,\) or \(2, 3\)"):
        frames.colour(ball, np.zeros((3, 3)))


def test_a_colour_follows_its_body_out_of_the_world_and_back():
    world = p2.World()
    first = world.add(p2.Circle(position=(-0.5, 0.0), radius=0.2))
    frames = Frames(world, 20, 20)
    frames.colour(first, (255, 0, 0))
    world.remove(first)
    other = world.add(p2.Circle(position=(0.5, 0.0), radius=0.2))  # takes the freed slot
    assert other.slot == 0
    assert frames()[0, 10, 15].tolist() != [255, 0, 0]  # not the removed body's colour
    world.add(first)
    assert frames()[0, 10, 5].tolist() == [255, 0, 0]
