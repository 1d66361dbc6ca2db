"""Why the soft step, and how many substeps: quality against cost, with pymunk alongside.

impulse2d solves contacts with Box2D v3's soft step (per substep: solve with a soft
position bias, integrate, relax without it; restitution once at the end). pymunk
(Chipmunk) uses sequential impulses with Baumgarte-style position correction and 10
iterations. This prints, for substeps 1, 2, 4 and 8 and for pymunk:

* the 20-row pyramid (210 boxes): drift of the top box and of any box after 10 s, and
  ms/step;
* the pool break: the deepest ball-ball overlap seen during the break (a solver that
  cannot push the rack apart in time lets balls sink into each other), the largest
  kinetic energy relative to what drag alone leaves (must not exceed 1), and
  world-steps/s at 256 worlds.

Run: ``python bench/solver_choice.py`` (about two minutes).
"""

from __future__ import annotations

import math
import time

import numpy as np
import pymunk

import impulse2d as p2

try:
    from bench.scenes import pool_break, pyramid
except ImportError:
    from scenes import pool_break, pyramid


def pyramid_quality(substeps: int, base: int = 20) -> tuple[float, float, float]:
    """Top-box drift, largest drift (m) after 10 s, and ms/step over the first 300 steps."""
    scene = pyramid(base)
    world = p2.World(gravity=scene.gravity, substeps=substeps, sleeping=False)
    ground = scene.ground
    world.add(
        p2.Box(
            position=ground.center,
            width=2 * ground.half_extents[0],
            height=2 * ground.half_extents[1],
            fixed=True,
            friction=scene.friction,
        )
    )
    boxes = [
        world.add(
            p2.Box(
                position=p,
                width=scene.box_size,
                height=scene.box_size,
                mass=scene.box_mass,
                friction=scene.friction,
            )
        )
        for p in scene.positions
    ]
    start = np.array([b.position for b in boxes])
    began = time.perf_counter()
    for _ in range(300):
        world.step(scene.dt)
    ms = (time.perf_counter() - began) / 300 * 1e3
    for _ in range(300):
        world.step(scene.dt)
    drift = np.linalg.norm(np.array([b.position for b in boxes]) - start, axis=1)
    return float(drift[scene.top_index]), float(drift.max()), ms


def pool_quality(substeps: int, worlds: int = 256) -> tuple[float, float, float]:
    """Deepest ball overlap (mm), largest KE / (KE0 exp(-2 d t)), world-steps/s."""
    scene = pool_break()
    world = p2.World(
        gravity=scene.gravity,
        substeps=substeps,
        restitution_mixing="min",
        restitution_threshold=0.05,
    )
    for box in scene.cushions:
        world.add(
            p2.Box(
                position=box.center,
                width=2 * box.half_extents[0],
                height=2 * box.half_extents[1],
                fixed=True,
                restitution=scene.restitution_ball_cushion,
                friction=scene.friction,
            )
        )
    balls = [
        world.add(
            p2.Circle(
                position=p,
                velocity=v,
                radius=scene.ball_radius,
                mass=scene.ball_mass,
                restitution=scene.restitution_ball_ball,
                friction=scene.friction,
                linear_drag=scene.linear_drag,
            )
        )
        for p, v in zip(scene.positions, scene.velocities, strict=True)
    ]
    batch = world.replicate(worlds)
    overlap, gain = 0.0, 0.0
    ke0 = 0.5 * scene.ball_mass * float((scene.velocities**2).sum())
    for step in range(1, 301):
        world.step(scene.dt)
        p = np.array([b.position for b in balls])
        v = np.array([b.velocity for b in balls])
        d = np.linalg.norm(p[:, None] - p[None], axis=-1) + np.eye(len(balls))
        overlap = max(overlap, 2 * scene.ball_radius - d.min())
        ke = 0.5 * scene.ball_mass * float((v**2).sum())
        gain = max(gain, ke / (ke0 * math.exp(-2 * scene.linear_drag * step * scene.dt)))
    began = time.perf_counter()
    for _ in range(scene.steps):
        batch.step(scene.dt)
    rate = worlds * scene.steps / (time.perf_counter() - began)
    return overlap * 1e3, gain, rate


def pymunk_pool_overlap() -> float:
    """The deepest ball-ball overlap (mm) in pymunk's pool break (same scene, 300 steps)."""
    scene = pool_break()
    space = pymunk.Space()
    space.damping = math.exp(-scene.linear_drag)
    for box in scene.cushions:
        shape = pymunk.Poly.create_box(
            space.static_body, (2 * box.half_extents[0], 2 * box.half_extents[1])
        )
        shape.body.position = (0, 0)
        shape.unsafe_set_vertices(
            [(x + box.center[0], y + box.center[1]) for x, y in shape.get_vertices()]
        )
        shape.elasticity = scene.restitution_ball_cushion / math.sqrt(scene.restitution_ball_ball)
        space.add(shape)
    bodies = []
    for p, v in zip(scene.positions, scene.velocities, strict=True):
        moment = pymunk.moment_for_circle(scene.ball_mass, 0, scene.ball_radius)
        body = pymunk.Body(scene.ball_mass, moment)
        body.position, body.velocity = tuple(p), tuple(v)
        shape = pymunk.Circle(body, scene.ball_radius)
        shape.elasticity = math.sqrt(scene.restitution_ball_ball)
        space.add(body, shape)
        bodies.append(body)
    overlap = 0.0
    for _ in range(300):
        space.step(scene.dt)
        p = np.array([tuple(b.position) for b in bodies])
        d = np.linalg.norm(p[:, None] - p[None], axis=-1) + np.eye(len(bodies))
        overlap = max(overlap, 2 * scene.ball_radius - d.min())
    return overlap * 1e3


def main() -> None:
    print(
        "substeps | pyramid 20: top drift, max drift (m), ms/step | pool: overlap (mm), "
        "KE gain, world-steps/s at 256 worlds"
    )
    for substeps in (1, 2, 4, 8):
        top, worst, ms = pyramid_quality(substeps)
        overlap, gain, rate = pool_quality(substeps)
        print(
            f"{substeps:8d} | {top:8.4f} {worst:8.4f} {ms:7.2f} | {overlap:6.1f} {gain:6.3f} "
            f"{rate:10,.0f}"
        )
    print(
        f"pymunk (10 iterations): pool overlap {pymunk_pool_overlap():.1f} mm; pyramid drift: "
        "see bench_engine.py"
    )


if __name__ == "__main__":
    main()
