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
  world-steps/s at 256 worlds (a ``World.step`` call a step, on the batch's default
  threads: every core numba sees).

Run: ``python bench/solver_choice.py`` (a few seconds).
"""

from __future__ import annotations

import math
import time

import numpy as np

try:
    from bench.bench_engine import _pool_world, _pyramid_world
    from bench.pymunk_peer import _pool_space
    from bench.scenes import pool_break, pyramid
except ImportError:
    from bench_engine import _pool_world, _pyramid_world
    from pymunk_peer import _pool_space
    from scenes import pool_break, pyramid


def pyramid_quality(substeps: int, base: int = 20) -> tuple[float, float, float]:
    """Top-box drift, largest drift (m) after 10 s, and ms/step over the first 300 steps."""
    scene = pyramid(base)
    world, indices = _pyramid_world(scene)
    world.substeps = substeps
    boxes = [world.bodies[k] for k in indices]
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
    world, indices, _ = _pool_world(scene, substeps=substeps, sleeping=True)
    balls = [world.bodies[k] for k in indices]
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
    space, bodies = _pool_space(scene)
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
