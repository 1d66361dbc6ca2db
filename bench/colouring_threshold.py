"""Whole steps coloured against plain order, by world size: where colouring pays.

Box pyramids of 3 to 20 rows on a fixed box (1 m boxes, friction 0.6, dt 1/60 s, 4
substeps, sleeping off), each stepped 20 steps, then timed over ``--steps`` steps in one
``World.step`` call from a snapshot, median of 5, once with every world in plain order
(``colouring.COLOUR_FROM_POINTS`` past any count) and once with every world coloured (0).
Prints µs a step and the ratio; ``docs/solver_layout.md`` quotes it.
"""

from __future__ import annotations

import argparse
import statistics
import time

import impulse2d as p2
from impulse2d.core import colouring


def pyramid(rows: int, colour_from: float) -> p2.World:
    """A pyramid of ``rows`` rows, coloured from ``colour_from`` points a step."""
    colouring.COLOUR_FROM_POINTS = colour_from  # read when the world's first step runs
    world = p2.World(substeps=4, sleeping=False)
    world.add(p2.Box(position=(0.0, -0.5), width=40.0, height=1.0, fixed=True, friction=0.6))
    for row in range(rows):
        for j in range(rows - row):
            x = (j - (rows - row - 1) / 2) * 1.05
            world.add(p2.Box(position=(x, 0.5 + row), width=1.0, height=1.0, friction=0.6))
    return world


def step_us(rows: int, colour_from: float, steps: int) -> tuple[float, int]:
    """µs a step of the pyramid, and its contact points."""
    world = pyramid(rows, colour_from)
    world.step(1 / 60, steps=20)
    start = world.snapshot()
    times = []
    for _ in range(5):
        world.restore(start)
        t0 = time.perf_counter()
        world.step(1 / 60, steps=steps)
        times.append(time.perf_counter() - t0)
    return statistics.median(times) / steps * 1e6, len(world.contacts().slot_a)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=200)
    parser.add_argument("--quick", action="store_true", help="two sizes, a few steps")
    args = parser.parse_args()
    sizes, steps = ((3, 6), 5) if args.quick else ((3, 4, 5, 6, 8, 10, 14, 20), args.steps)
    default = colouring.COLOUR_FROM_POINTS
    print(f"{'rows':>4}  {'points':>6}  {'plain us':>8}  {'coloured us':>11}  ratio", flush=True)
    try:
        for rows in sizes:
            plain, points = step_us(rows, float("inf"), steps)
            coloured, _ = step_us(rows, 0.0, steps)
            row = f"{rows:4d}  {points:6d}  {plain:8.1f}  {coloured:11.1f}  {coloured / plain:5.2f}"
            print(row, flush=True)
    finally:
        colouring.COLOUR_FROM_POINTS = default


if __name__ == "__main__":
    main()
