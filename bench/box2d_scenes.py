"""Box2D v3's benchmark scenes that need polygons, capsules, segments or joints, built in
impulse2d and in Box2D v3 (``pyb2d3``) from the same numbers and timed side by side.

From Box2D's ``shared/benchmarks.c`` (read, not copied), one world, 60 Hz, 4 substeps,
sleeping as Box2D's scene says, each scene's own step count:

* ``joint_grid``: 100 x 100 discs (r 0.4 m, 1 m apart) pinned to their right and lower
  neighbours by revolute joints (19,800), seven of the first column fixed, hanging under
  gravity; 500 steps. Box2D filters every collision among the grid's discs; impulse2d
  keeps joined neighbours apart (``collide_connected=False``), so discs that are not
  neighbours may still touch as the grid sags.
* ``smash``: a heavy 8 m box at 40 m/s into a resting block of 120 x 80 boxes of 0.4 m,
  no gravity, the block asleep at the start; 300 steps.
* ``tumbler``: 2,025 boxes of 0.25 m in a 20 m square drum turning at 25 degrees a second;
  750 steps. Box2D's drum is one body of four box shapes on a motor; impulse2d has no
  compound bodies, so its drum is four kinematic boxes turned rigidly about the centre
  (each step's velocity takes each wall to where the turning drum puts it).
* ``spinner``: 6,076 capsules, discs and squares in a ring of 360 segments (r 40 m), a
  rounded 0.8 x 40 m paddle on a revolute motor at 5 rad/s; 500 steps. (impulse2d's
  paddle is 0.5 m shorter: its segments are two-sided, Box2D's chain one-sided.)
* ``many_pyramids``: 20 x 20 pyramids of 10 rows (22,000 boxes) on 20 ground segments;
  200 steps.

``--quick`` takes Box2D's own debug sizes (20 x 20 grid, 20 x 10 block, 20 x 20 boxes,
499 bodies, 5 x 5 pyramids) and fewer steps. Run ``python bench/box2d_scenes.py``.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))
import impulse2d as p2

try:
    import pyb2d3
except ImportError:  # the bench extra is not installed: "not installed" in the table
    pyb2d3 = None

DT, SUBSTEPS = 1 / 60, 4


@dataclass(frozen=True)
class Sizes:
    grid: int = 100
    smash: tuple[int, int] = (120, 80)
    tumbler: int = 45
    spinner: int = 2 * 3038
    pyramids: int = 20
    steps: dict[str, int] | None = None


FULL = Sizes(steps={"joint_grid": 500, "smash": 300, "tumbler": 750, "spinner": 500,
                    "many_pyramids": 200})  # fmt: skip
QUICK = Sizes(20, (20, 10), 20, 499, 5, {"joint_grid": 100, "smash": 100, "tumbler": 150,
                                         "spinner": 100, "many_pyramids": 60})  # fmt: skip


# -- impulse2d --------------------------------------------------------------------------------
def joint_grid_impulse2d(n: int) -> tuple[p2.World, Callable[[p2.World], None]]:
    world = p2.World(substeps=SUBSTEPS, sleeping=False)
    bodies: list[Any] = []
    for k in range(n):
        for i in range(n):
            fixed = n // 2 - 3 <= k <= n // 2 + 3 and i == 0
            disc = world.add(
                p2.Circle(radius=0.4, position=(k, -i), fixed=fixed, mass=math.pi * 0.16)
            )
            if i > 0:
                world.add(p2.RevoluteJoint(bodies[-1], disc, anchor=(k, -i + 0.5)))
            if k > 0:
                world.add(p2.RevoluteJoint(bodies[-n], disc, anchor=(k - 0.5, -i)))
            bodies.append(disc)
    return world, _nothing


def smash_impulse2d(columns: int, rows: int) -> tuple[p2.World, Callable[[p2.World], None]]:
    world = p2.World(gravity=(0.0, 0.0), substeps=SUBSTEPS)
    d = 0.4
    for i in range(columns):
        for j in range(rows):
            world.add(p2.Box(width=d, height=d, position=(i * d + 30.0, (j - rows / 2) * d),
                             mass=d * d))  # fmt: skip
    world.stop()  # the block starts asleep, as Box2D's
    world.add(
        p2.Box(width=8.0, height=8.0, position=(-20.0, 0.0), velocity=(40.0, 0.0), mass=512.0)
    )
    return world, _nothing


def tumbler_impulse2d(grid: int) -> tuple[p2.World, Callable[[p2.World], None]]:
    world = p2.World(substeps=SUBSTEPS)
    centre, omega = np.array([0.0, 10.0]), math.radians(25.0)
    walls = []
    for offset, (hw, hh) in (((10, 0), (0.5, 10)), ((-10, 0), (0.5, 10)), ((0, 10), (10, 0.5)),
                             ((0, -10), (10, 0.5))):  # fmt: skip
        wall = world.add(
            p2.Box(width=2 * hw, height=2 * hh, position=tuple(centre + offset), kinematic=True)
        )
        walls.append((wall, np.array(offset, float)))
    y = -0.2 * grid + 10.0
    for _ in range(grid):
        x = -0.2 * grid
        for _ in range(grid):
            world.add(p2.Box(width=0.25, height=0.25, position=(x, y), mass=0.0625))
            x += 0.4
        y += 0.4

    def turn(world: p2.World) -> None:
        # Each wall moves along the chord to where the rigid drum puts it after this step.
        angle = float(world.time) * omega
        c0, s0 = math.cos(angle), math.sin(angle)
        c1, s1 = math.cos(angle + omega * DT), math.sin(angle + omega * DT)
        for wall, offset in walls:
            now = centre + np.array(
                [c0 * offset[0] - s0 * offset[1], s0 * offset[0] + c0 * offset[1]]
            )
            then = centre + np.array(
                [c1 * offset[0] - s1 * offset[1], s1 * offset[0] + c1 * offset[1]]
            )
            wall.velocity = (then - now) / DT
            wall.angular_velocity = omega

    turn(world)
    return world, turn


def spinner_impulse2d(count: int) -> tuple[p2.World, Callable[[p2.World], None]]:
    world = p2.World(substeps=SUBSTEPS)
    ring = _ring()
    for a, b in zip(ring, ring[1:] + ring[:1], strict=True):
        world.add(p2.Segment(start=a, end=b, friction=0.1))
    hub = world.add(p2.Circle(radius=0.1, position=(0.0, 12.0), fixed=True))
    # Box2D's rounded box is a 0.8 x 40 m core rounded by 0.2 m, reaching 0.2 m past the
    # ring at the bottom of its turn: Box2D's chain is one-sided and lets it through from
    # behind. impulse2d's segments are solid from both sides, so its core is 0.5 m shorter
    # (the paddle clears the ring by 5 cm).
    core = [(0.4, 19.75), (-0.4, 19.75), (-0.4, -19.75), (0.4, -19.75)]
    area = 0.8 * 39.5 + 0.2 * 2 * (0.8 + 39.5) + math.pi * 0.04
    paddle = world.add(p2.Polygon(vertices=core, radius=0.2, position=(0.0, 12.0), friction=0.0,
                                  mass=area))  # fmt: skip
    world.add(
        p2.RevoluteJoint(hub, paddle, anchor=(0.0, 12.0), motor_speed=5.0, max_motor_torque=1e12)
    )
    x, y = -23.0, 2.0
    material = {"friction": 0.1, "restitution": 0.1}
    for i in range(count):
        if i % 3 == 0:
            body = p2.Capsule(length=0.5, radius=0.25, mass=0.25 * (0.5 * 0.5 + math.pi * 0.0625))
        elif i % 3 == 1:
            body = p2.Circle(radius=0.35, mass=0.25 * math.pi * 0.1225)
        else:
            body = p2.Box(width=0.7, height=0.7, mass=0.25 * 0.49)
        body.position = (x, y)
        for name, value in material.items():
            setattr(body, name, value)
        world.add(body)
        x += 0.5
        if x >= 23.0:
            x, y = -23.0, y + 0.5
    return world, _nothing


def many_pyramids_layout(count: int) -> tuple[list, list]:
    """``count`` x ``count`` pyramids of 10 rows of 1 m boxes: the ground segments (one a
    row of pyramids) and the boxes' centres, as Box2D's ``CreateManyPyramids`` places them."""
    base, extent = 10, 0.5
    dy, width = 2 * extent * (base + 1), 2 * extent * count * (base + 1)
    grounds = [((-0.5 * width, i * dy), (0.5 * width, i * dy)) for i in range(count)]
    centres = []
    for row in range(count):
        for column in range(count):
            centre_x = -0.5 * width + column * (2 * extent * base + 2 * extent) + 2 * extent
            for i in range(base):
                y = (2 * i + 1) * extent + row * dy
                for j in range(i, base):
                    centres.append(((i + 1) * extent + 2 * (j - i) * extent + centre_x - 0.5, y))
    return grounds, centres


def many_pyramids_impulse2d(count: int) -> tuple[p2.World, Callable[[p2.World], None]]:
    world = p2.World(substeps=SUBSTEPS, sleeping=False)
    grounds, centres = many_pyramids_layout(count)
    for start, end in grounds:
        world.add(p2.Segment(start=start, end=end))
    for centre in centres:
        world.add(p2.Box(width=1.0, height=1.0, position=centre))
    return world, _nothing


def _ring() -> list[tuple[float, float]]:
    """The spinner's 360 ring points, clockwise from (40, 32), radius 40 m about (0, 32)."""
    turn = -2.0 * math.pi / 360
    return [(40.0 * math.cos(turn * i), 40.0 * math.sin(turn * i) + 32.0) for i in range(360)]


def _nothing(world: p2.World) -> None:
    """A scene with nothing to do between steps."""


# -- Box2D v3 ------------------------------------------------------------------------------------
def _b2world(gravity=(0.0, -10.0), sleeping: bool = True) -> Any:
    world = pyb2d3.World(gravity=gravity)
    world.sleeping_enabled = sleeping
    return world


def _shape(density: float = 1.0, friction: float = 0.6, restitution: float = 0.0, **more) -> Any:
    material = pyb2d3.surface_material(friction=friction, restitution=restitution)
    return pyb2d3.shape_def(density=density, material=material, **more)


def joint_grid_box2d(n: int) -> Any:
    world = _b2world(sleeping=False)
    filt = pyb2d3.make_filter(category_bits=2, mask_bits=~2 & 0xFFFFFFFFFFFFFFFF)
    shape = _shape(filter=filt)
    bodies = []
    for k in range(n):
        for i in range(n):
            static = n // 2 - 3 <= k <= n // 2 + 3 and i == 0
            make = world.create_static_body if static else world.create_dynamic_body
            body = make(position=(float(k), float(-i)))
            body.create_shape(shape, pyb2d3.circle(radius=0.4))
            if i > 0:
                world.create_revolute_joint(pyb2d3.revolute_joint_def(
                    body_a=bodies[-1], body_b=body, local_anchor_a=(0.0, -0.5),
                    local_anchor_b=(0.0, 0.5)))  # fmt: skip
            if k > 0:
                world.create_revolute_joint(pyb2d3.revolute_joint_def(
                    body_a=bodies[-n], body_b=body, local_anchor_a=(0.5, 0.0),
                    local_anchor_b=(-0.5, 0.0)))  # fmt: skip
            bodies.append(body)
    return world


def smash_box2d(columns: int, rows: int) -> Any:
    world = _b2world(gravity=(0.0, 0.0))
    big = world.create_dynamic_body(position=(-20.0, 0.0), linear_velocity=(40.0, 0.0))
    big.create_shape(_shape(density=8.0), pyb2d3.box(4.0, 4.0))
    d = 0.4
    for i in range(columns):
        for j in range(rows):
            body = world.create_dynamic_body(
                position=(i * d + 30.0, (j - rows / 2) * d), is_awake=False
            )
            body.create_shape(_shape(), pyb2d3.box(0.5 * d, 0.5 * d))
    return world


def tumbler_box2d(grid: int) -> Any:
    world = _b2world()
    ground = world.create_static_body(position=(0.0, 0.0))
    drum = world.create_dynamic_body(position=(0.0, 10.0))
    for offset, (hw, hh) in (((10, 0), (0.5, 10)), ((-10, 0), (0.5, 10)), ((0, 10), (10, 0.5)),
                             ((0, -10), (10, 0.5))):  # fmt: skip
        drum.create_shape(_shape(density=50.0), pyb2d3.box(hw, hh, center=offset))
    world.create_revolute_joint(pyb2d3.revolute_joint_def(
        body_a=ground, body_b=drum, local_anchor_a=(0.0, 10.0), local_anchor_b=(0.0, 0.0),
        motor_speed=math.radians(25.0), max_motor_torque=1e8, enable_motor=True))  # fmt: skip
    y = -0.2 * grid + 10.0
    for _ in range(grid):
        x = -0.2 * grid
        for _ in range(grid):
            body = world.create_dynamic_body(position=(x, y))
            body.create_shape(_shape(), pyb2d3.box(0.125, 0.125))
            x += 0.4
        y += 0.4
    return world


def spinner_box2d(count: int) -> Any:
    world = _b2world()
    ground = world.create_static_body(position=(0.0, 0.0))
    ring = _ring()
    material = pyb2d3.surface_material(friction=0.1)
    ground.create_chain(pyb2d3.chain_def(points=ring, is_loop=True, material=material))
    paddle = world.create_dynamic_body(position=(0.0, 12.0), enable_sleep=False)
    paddle.create_shape(_shape(friction=0.0), pyb2d3.box(0.4, 20.0, radius=0.2))
    world.create_revolute_joint(pyb2d3.revolute_joint_def(
        body_a=ground, body_b=paddle, local_anchor_a=(0.0, 12.0), local_anchor_b=(0.0, 0.0),
        motor_speed=5.0, max_motor_torque=3.4e38, enable_motor=True))  # fmt: skip
    shape = _shape(density=0.25, friction=0.1, restitution=0.1)
    x, y = -23.0, 2.0
    for i in range(count):
        body = world.create_dynamic_body(position=(x, y))
        if i % 3 == 0:
            body.create_shape(shape, pyb2d3.capsule((-0.25, 0.0), (0.25, 0.0), 0.25))
        elif i % 3 == 1:
            body.create_shape(shape, pyb2d3.circle(radius=0.35))
        else:
            body.create_shape(shape, pyb2d3.box(0.35, 0.35))
        x += 0.5
        if x >= 23.0:
            x, y = -23.0, y + 0.5
    return world


def many_pyramids_box2d(count: int) -> Any:
    world = _b2world(sleeping=False)
    ground = world.create_static_body(position=(0.0, 0.0))
    grounds, centres = many_pyramids_layout(count)
    for start, end in grounds:
        ground.create_shape(_shape(), pyb2d3.segment(start, end))
    for centre in centres:
        body = world.create_dynamic_body(position=centre)
        body.create_shape(_shape(), pyb2d3.box(0.5, 0.5))
    return world


# -- timing ----------------------------------------------------------------------------------------
def time_impulse2d(build: Callable[[], tuple[p2.World, Callable]], steps: int) -> dict:
    start = time.perf_counter()
    world, between = build()
    built = time.perf_counter() - start
    world.step(DT)  # compiled kernels loaded, room made: untimed
    between(world)
    times = []
    for _ in range(steps - 1):
        t0 = time.perf_counter()
        world.step(DT)
        times.append(time.perf_counter() - t0)
        between(world)
    finite = bool(np.isfinite(world.state.body[..., :6]).all())
    return {"ms": 1e3 * float(np.mean(times)), "median": 1e3 * float(np.median(times)),
            "build_s": built, "finite": finite, "world": world}  # fmt: skip


def time_box2d(build: Callable[[], Any], steps: int) -> dict | None:
    if pyb2d3 is None:
        return None
    world = build()
    world.step(DT, SUBSTEPS)
    start = time.perf_counter()
    for _ in range(steps - 1):
        world.step(DT, SUBSTEPS)
    return {"ms": 1e3 * (time.perf_counter() - start) / (steps - 1)}


def scenes(sizes: Sizes) -> list[tuple[str, str, Callable, Callable]]:
    """(name, description, impulse2d builder, Box2D builder) of each scene."""
    n, (cols, rows), grid, count, pyr = (sizes.grid, sizes.smash, sizes.tumbler, sizes.spinner,
                                         sizes.pyramids)  # fmt: skip
    return [
        ("joint_grid", f"{n}x{n} discs, {2 * n * (n - 1):,} revolute joints",
         lambda: joint_grid_impulse2d(n), lambda: joint_grid_box2d(n)),
        ("smash", f"{cols * rows:,} boxes hit at 40 m/s", lambda: smash_impulse2d(cols, rows),
         lambda: smash_box2d(cols, rows)),
        ("tumbler", f"{grid * grid:,} boxes in a turning drum", lambda: tumbler_impulse2d(grid),
         lambda: tumbler_box2d(grid)),
        ("spinner", f"{count:,} capsules, discs, squares; a motor paddle",
         lambda: spinner_impulse2d(count), lambda: spinner_box2d(count)),
        ("many_pyramids", f"{pyr * pyr} pyramids, {pyr * pyr * 55:,} boxes",
         lambda: many_pyramids_impulse2d(pyr), lambda: many_pyramids_box2d(pyr)),
    ]  # fmt: skip


def rows(
    quick: bool, only: list[str] | None = None, progress: Callable[[str], None] = print
) -> list[tuple[str, ...]]:
    """One row per scene as ``bench_engine``'s table has them (scene, worlds, impulse2d,
    pymunk, ratio, Box2D v3, impulse2d / Box2D, notes): ms a step, pymunk not run."""
    sizes = QUICK if quick else FULL
    out = []
    for name, what, mine, theirs in scenes(sizes):
        if only and name not in only:
            continue
        steps = sizes.steps[name]
        progress(f"{name}: {what}, {steps} steps (impulse2d, then Box2D)")
        ri = time_impulse2d(mine, steps)
        rb = time_box2d(theirs, steps)
        b2 = f"{rb['ms']:.2f}" if rb else "not installed"
        ratio = f"{ri['ms'] / rb['ms']:.2f}x" if rb else "-"
        notes = (f"{what}; {steps} steps, mean (median {ri['median']:.2f} ms); build "
                 f"{ri['build_s']:.1f} s; finite {ri['finite']}")  # fmt: skip
        out.append(
            (f"{name} (Box2D's): ms/step", "1", f"{ri['ms']:.2f}", "-", "-", b2, ratio, notes)
        )
    return out


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true", help="Box2D's debug sizes, fewer steps")
    parser.add_argument("--only", nargs="*", help="scene names to run")
    args = parser.parse_args(argv)
    table = [(r[0], r[2], r[5], r[6], r[7]) for r in rows(args.quick, args.only)]
    header = ("scene", "impulse2d", "Box2D v3", "ratio", "notes")
    widths = [max(len(str(r[i])) for r in [header, *table]) for i in range(len(header))]
    for r in [header, tuple("-" * w for w in widths), *table]:
        print("  ".join(str(c).ljust(w) for c, w in zip(r, widths, strict=True)))


if __name__ == "__main__":
    main()
