"""Peer benchmark: the shared scenes from ``bench/scenes.py`` run in Box2D v3 (``pyb2d3``).

Box2D v3 is used as its own samples use it: one world, stepped with ``world.step(dt, 4)``
(4 substeps, the count Box2D's samples and benchmarks use), the default solver settings
(contact stiffness 30 Hz, damping ratio 10, push-out speed 3 m/s, continuous collision on),
sleeping off (``World.sleeping_enabled = False`` and ``enable_sleep=False`` on every
body), and no thread pool: the world steps on one thread, like the single impulse2d world
and pymunk it is compared with. Contact callbacks and events are never read in a timed
loop.

How the scene parameters map onto Box2D (checked against pyb2d3 0.11.1):

* Friction and restitution: Box2D mixes friction as ``sqrt(f1 f2)`` and restitution as
  ``max(e1, e2)``, so giving every shape the scene's coefficient gives every contact it.
* Mass: Box2D takes a density per shape; a box of ``w x h`` gets ``mass / (w h)`` and a
  circle ``mass / (pi r^2)``, so every body weighs the scene's mass (1 kg here).
* Static bodies: the scene's axis-aligned ``StaticBox`` as a static body with one box
  polygon (radius 0: sharp corners, as in the other engines).
* Positions come back as float32 (Box2D's precision); drifts are taken in float64 from
  them and the scene's float64 starting positions.

Scenes: the pyramids of :func:`scenes.pyramid` (timing and top-box drift, as
:func:`pymunk_peer.pyramid_pymunk`), the rain of :func:`scenes.rain` (as
:func:`pymunk_peer.rain_pymunk`) and Box2D's own ``large_pyramid`` benchmark
(:func:`scenes.large_pyramid`, 5,050 boxes, 500 steps). The pool break is not run: its
restitution mixes by ``min`` (0.95 ball-ball, 0.75 ball-cushion), which Box2D's ``max``
cannot give without a per-contact restitution callback, which pyb2d3 does not expose.

Without pyb2d3 installed this module still imports; :data:`AVAILABLE` is then False and
the benchmark prints "not installed" in the Box2D column. Run ``python bench/box2d_peer.py``
for its own table.
"""

from __future__ import annotations

import math
import time

import numpy as np

try:
    import pyb2d3
except ImportError:  # the bench extra is not installed: the benchmark shows "not installed"
    pyb2d3 = None

try:  # imported as part of the repo (``bench.box2d_peer``) ...
    from bench.scenes import (
        LATERAL_CREEP_M,
        Pyramid,
        Rain,
        StaticBox,
        large_pyramid,
        pyramid,
        pyramid_settling,
        rain,
        validate,
    )
except ImportError:  # ... or run as a script, with bench/ on sys.path
    from scenes import (
        LATERAL_CREEP_M,
        Pyramid,
        Rain,
        StaticBox,
        large_pyramid,
        pyramid,
        pyramid_settling,
        rain,
        validate,
    )

AVAILABLE = pyb2d3 is not None
SUBSTEPS = 4  # Box2D's samples and its benchmark programs step with 4 substeps


def version() -> str:
    """The binding's version, or that it is missing."""
    if not AVAILABLE:
        return "pyb2d3 not installed"
    from importlib.metadata import version as dist_version

    return f"pyb2d3 {dist_version('pyb2d3')}"


def _world(gravity: tuple[float, float], sleeping: bool = False) -> pyb2d3.World:
    """A single-threaded Box2D world with the default solver settings and sleeping off
    (or on, with Box2D's defaults: 0.5 s below 0.05 m/s)."""
    world = pyb2d3.World(gravity=gravity)  # no thread_pool: one thread
    world.sleeping_enabled = sleeping
    return world


def _shape_def(density: float, friction: float, restitution: float) -> pyb2d3.ShapeDef:
    material = pyb2d3.surface_material(friction=friction, restitution=restitution)
    return pyb2d3.shape_def(density=density, material=material)


def _add_static_box(world: pyb2d3.World, box: StaticBox, friction: float, e: float) -> None:
    """The scene's fixed axis-aligned box as a static body."""
    body = world.create_static_body(position=box.center)
    body.create_shape(_shape_def(1.0, friction, e), pyb2d3.box(*box.half_extents))


def _positions(bodies: pyb2d3.Bodies) -> np.ndarray:
    """Centre positions of ``bodies`` as an (n, 2) float64 array."""
    return bodies.get_positions().astype(np.float64)


def _warm_up() -> None:
    """Exercise Box2D's code paths once so first-call costs don't land in a timing."""
    world, _ = _pyramid_world(pyramid(4))
    for _ in range(60):
        world.step(1 / 60, SUBSTEPS)


# -- pyramids --------------------------------------------------------------------------------
def _pyramid_world(scene: Pyramid) -> tuple[pyb2d3.World, pyb2d3.Bodies]:
    """Build a pyramid scene (also the large one) in Box2D; the boxes in scene order."""
    world = _world(scene.gravity)
    _add_static_box(world, scene.ground, scene.friction, scene.restitution)
    size = scene.box_size
    shape_def = _shape_def(scene.box_mass / size**2, scene.friction, scene.restitution)
    polygon = pyb2d3.box(size / 2, size / 2)
    boxes = pyb2d3.Bodies()
    for p in scene.positions:
        body = world.create_dynamic_body(position=(float(p[0]), float(p[1])), enable_sleep=False)
        body.create_shape(shape_def, polygon)
        boxes.append(body.id)
    return world, boxes


def pyramid_box2d(base: int, steps: int = 300, drift_steps: int = 600) -> dict:
    """Time the first ``steps`` steps of a Box2D box pyramid, then measure its drift.

    As :func:`pymunk_peer.pyramid_pymunk`: stepping continues untimed up to ``drift_steps``;
    ``top_drift_m`` is how far the top box's centre has moved from its start,
    ``max_drift_m`` the largest such distance over all boxes.
    """
    scene = pyramid(base)
    validate(scene)
    world, boxes = _pyramid_world(scene)
    _warm_up()
    step, dt = world.step, scene.dt
    t0 = time.perf_counter()
    for _ in range(steps):
        step(dt, SUBSTEPS)
    seconds = time.perf_counter() - t0
    for _ in range(steps, drift_steps):
        step(dt, SUBSTEPS)
    pos = _positions(boxes)
    drift = np.linalg.norm(pos - scene.positions, axis=1)
    return {
        "ms_per_step": 1000 * seconds / steps,
        "top_drift_m": float(drift[scene.top_index]),
        "max_drift_m": float(drift.max()),
        "finite": bool(np.all(np.isfinite(pos))),
    }


def large_pyramid_box2d(steps: int | None = None) -> dict:
    """Box2D's ``large_pyramid`` benchmark: time ``steps`` steps (default the scene's 500)
    from the first, then measure how the pyramid has settled (:func:`scenes.pyramid_settling`).

    Returns ``ms_per_step``, ``build_s`` (building the world, untimed), ``steps`` and the
    measures of :func:`scenes.pyramid_settling`.
    """
    scene = large_pyramid()
    validate(scene)
    steps = scene.steps if steps is None else steps
    _warm_up()
    t0 = time.perf_counter()
    world, boxes = _pyramid_world(scene)
    build_s = time.perf_counter() - t0
    step, dt = world.step, scene.dt
    t0 = time.perf_counter()
    for _ in range(steps):
        step(dt, SUBSTEPS)
    seconds = time.perf_counter() - t0
    return {
        "ms_per_step": 1000 * seconds / steps,
        "build_s": build_s,
        "steps": steps,
        **pyramid_settling(scene, _positions(boxes)),
    }


# -- rain ------------------------------------------------------------------------------------
def _rain_world(scene: Rain, sleeping: bool = False) -> tuple[pyb2d3.World, list]:
    """Build the rain scene in Box2D (ground: the scene's finite static box, top face at
    y = 0); the falling bodies in scene order (a ``pyb2d3.Bodies`` and the bodies)."""
    world = _world(scene.gravity, sleeping)
    _add_static_box(world, scene.ground, scene.friction, scene.restitution)
    r, (w, h) = scene.circle_radius, scene.box_size
    mu, e = scene.friction, scene.restitution
    circle_def = _shape_def(scene.mass / (math.pi * r * r), mu, e)
    box_def = _shape_def(scene.mass / (w * h), mu, e)
    circle, polygon = pyb2d3.circle(radius=r), pyb2d3.box(w / 2, h / 2)
    bodies, each = pyb2d3.Bodies(), []
    for p, angle, is_circle in zip(scene.positions, scene.angles, scene.is_circle, strict=True):
        body = world.create_dynamic_body(
            position=(float(p[0]), float(p[1])), rotation=float(angle), enable_sleep=sleeping
        )
        body.create_shape(circle_def if is_circle else box_def, circle if is_circle else polygon)
        bodies.append(body.id)
        each.append(body)
    return world, [bodies, each]


def _rain_ms(world: pyb2d3.World, dt: float, steps: int, settle_steps: int) -> float:
    """ms a step over ``steps`` steps of ``world`` after ``settle_steps`` untimed ones."""
    _warm_up()
    for _ in range(settle_steps):
        world.step(dt, SUBSTEPS)
    t0 = time.perf_counter()
    for _ in range(steps):
        world.step(dt, SUBSTEPS)
    return 1000 * (time.perf_counter() - t0) / steps


def rain_box2d(count: int, steps: int = 120, settle_steps: int = 60) -> dict:
    """Time ``steps`` steps of the Box2D rain scene after ``settle_steps`` untimed ones, as
    :func:`pymunk_peer.rain_pymunk`. Returns ``ms_per_step``, ``mean_y`` (mean height of
    the bodies' centres at the end, m) and ``finite``."""
    scene = rain(count)
    validate(scene)
    world, (bodies, _) = _rain_world(scene)
    ms = _rain_ms(world, scene.dt, steps, settle_steps)
    pos = _positions(bodies)
    return {
        "ms_per_step": ms,
        "mean_y": float(pos[:, 1].mean()),
        "finite": bool(np.all(np.isfinite(pos))),
    }


def settled_rain_box2d(count: int, steps: int = 120, settle_steps: int = 600) -> dict:
    """The rain with sleeping on: ``settle_steps`` untimed steps (the piles come to rest
    and fall asleep), then ``steps`` timed. Returns ``ms_per_step`` and ``awake`` (bodies
    awake at the end)."""
    scene = rain(count)
    world, (_, each) = _rain_world(scene, sleeping=True)
    ms = _rain_ms(world, scene.dt, steps, settle_steps)
    return {"ms_per_step": ms, "awake": sum(b.awake for b in each)}


def main() -> None:
    """Print this peer's own table (one run of each scene)."""
    if not AVAILABLE:
        raise SystemExit("pyb2d3 is not installed: pip install -e '.[bench]'")
    t_start = time.perf_counter()
    print(f"Box2D v3 via {version()}, {SUBSTEPS} substeps, sleeping off, one thread\n")
    print(f"{'scene':<28}{'ms/step':>9}{'top drift m':>13}{'max drift m':>13}")
    for base in (10, 20):
        res = pyramid_box2d(base)
        print(
            f"{f'pyramid base {base}':<28}{res['ms_per_step']:>9.3f}"
            f"{res['top_drift_m']:>13.4f}{res['max_drift_m']:>13.4f}"
        )
    print(f"\n{'scene':<28}{'ms/step':>9}{'mean y m':>13}")
    for count in (250, 1000, 4000):
        res = rain_box2d(count)
        print(f"{f'rain {count}':<28}{res['ms_per_step']:>9.3f}{res['mean_y']:>13.3f}")
    res = large_pyramid_box2d()
    print(
        f"\nlarge_pyramid, {res['steps']} steps: {res['ms_per_step']:.3f} ms/step; apex sank "
        f"{res['apex_sink_m']:.4f} m, max |dx| {res['max_dx_m']:.4f} m, {res['crept']} boxes "
        f"moved > {LATERAL_CREEP_M} m sideways"
    )
    print(f"\ntotal {time.perf_counter() - t_start:.1f} s")


if __name__ == "__main__":
    main()
