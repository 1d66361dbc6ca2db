"""A short tour of the engine: ``python -m impulse2d``.

Runs a few of the tutorial's milestones headless and prints what they measure: a ball
bouncing with its energy readout, a box dropped at an angle settling flat, a 55-box
pyramid standing, a spring's period, and a pool break stepped in 256 worlds at once.
It takes a few seconds and needs nothing but the engine (numpy and numba).
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

import impulse2d as p2


def bouncing_ball() -> str:
    """Milestones 1-5: gravity, a plane, restitution, and the energy readout."""
    world = p2.World(gravity=(0.0, -9.81), sleeping=False)
    world.add(p2.Plane(normal=(0.0, 1.0), point=(0.0, 0.0), restitution=0.8))
    ball = world.add(p2.Circle(position=(0.0, 2.5), radius=0.5, restitution=0.8))
    apexes, rising = [], False
    for _ in range(360):
        before = ball.velocity[1]
        world.step(1 / 60)
        if before > 0.0 >= ball.velocity[1] and rising:
            apexes.append(ball.position[1] - 0.5)
        rising = ball.velocity[1] > 0.0
    ratios = [b / a for a, b in zip([2.0, *apexes], apexes, strict=False)]
    return (
        f"ball dropped 2 m, e = 0.8: apex heights {', '.join(f'{h:.3f}' for h in apexes[:4])}"
        f" m; each / previous {np.mean(ratios[:4]):.3f} (theory e^2 = 0.640)"
    )


def tilted_box() -> str:
    """Milestones 6-8: a box, rotation and torque, box-plane contact."""
    world = p2.World(gravity=(0.0, -9.81))
    world.add(p2.Plane(friction=0.6))
    box = world.add(p2.Box(position=(0.0, 2.0), width=1.0, height=0.5, angle=0.6))
    for _ in range(240):
        world.step(1 / 60)
    flat = min(abs(box.angle - k * math.pi / 2) for k in range(-4, 5))
    return (
        f"box dropped at 0.6 rad: settles {flat:.1e} rad from flat at height "
        f"{box.position[1]:.3f} m, asleep: {not box.awake}"
    )


def pyramid() -> str:
    """Milestones 11-12 and the contact extra: box stacking with friction."""
    world = p2.World(gravity=(0.0, -9.81), sleeping=False)
    world.add(p2.Plane())
    boxes = [
        world.add(p2.Box(position=((i - (10 - row - 1) / 2) * 1.05, 0.5 + row)))
        for row in range(10)
        for i in range(10 - row)
    ]
    start = np.array([b.position for b in boxes])
    began = time.perf_counter()
    for _ in range(600):
        world.step(1 / 60)
    took = (time.perf_counter() - began) / 600
    drift = np.abs(np.array([b.position for b in boxes]) - start).max()
    return f"55-box pyramid, 10 s: largest drift {drift * 1000:.1f} mm; {took * 1e3:.2f} ms/step"


def spring() -> str:
    """The springs extra: period against 2 pi sqrt(m / k)."""
    world = p2.World(gravity=(0.0, 0.0))
    anchor = world.add(p2.Circle(position=(0.0, 0.0), radius=0.1, fixed=True))
    mass = world.add(p2.Circle(position=(1.5, 0.0), radius=0.1, mass=2.0))
    world.add(p2.Spring(anchor, mass, rest_length=1.0, stiffness=20.0))
    crossings, last = [], mass.position[0] - 1.0
    for step in range(1200):
        world.step(1 / 120)
        now = mass.position[0] - 1.0
        if last > 0.0 >= now:
            crossings.append(step / 120)
        last = now
    period = float(np.mean(np.diff(crossings)))
    theory = 2 * math.pi * math.sqrt(2.0 / 20.0)
    return f"spring k = 20 N/m, m = 2 kg: period {period:.4f} s (theory {theory:.4f} s)"


def pool_batch(worlds: int) -> str:
    """The batched core: one pool break stepped in many worlds at once."""
    world = p2.World(
        gravity=(0.0, 0.0), substeps=2, restitution_mixing="min", restitution_threshold=0.05
    )
    for x, y, w, h in (
        (0, 0.685, 2.74, 0.1),
        (0, -0.685, 2.74, 0.1),
        (1.32, 0, 0.1, 1.27),
        (-1.32, 0, 0.1, 1.27),
    ):
        world.add(p2.Box(position=(x, y), width=w, height=h, fixed=True, restitution=0.75))
    r = 0.028575
    world.add(
        p2.Circle(
            position=(-0.635, 0.0),
            radius=r,
            mass=0.17,
            velocity=(8.0, 0.0),
            restitution=0.95,
            friction=0.0,
            linear_drag=0.7,
        )
    )
    for row in range(5):
        for k in range(row + 1):
            position = (0.635 + row * 2.0001 * r * math.sqrt(3) / 2, (k - row / 2) * 2.0001 * r)
            world.add(
                p2.Circle(
                    position=position,
                    radius=r,
                    mass=0.17,
                    restitution=0.95,
                    friction=0.0,
                    linear_drag=0.7,
                )
            )
    batch = world.replicate(worlds)
    began = time.perf_counter()
    for _ in range(1200):
        batch.step(1 / 120)
    rate = worlds * 1200 / (time.perf_counter() - began)
    return f"16-ball pool break, 1,200 steps in {worlds} worlds at once: {rate:,.0f} world-steps/s"


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description="A short tour of the impulse2d engine.")
    parser.add_argument("--worlds", type=int, default=256, help="worlds in the pool batch")
    args = parser.parse_args(argv)
    print(f"impulse2d {p2.__version__}: a tour of the tutorial's milestones")
    for demo in (bouncing_ball, tilted_box, pyramid, spring):
        print(f"- {demo()}")
    print(f"- {pool_batch(args.worlds)}")


if __name__ == "__main__":
    main()
