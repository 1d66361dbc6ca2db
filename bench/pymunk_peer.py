"""Peer benchmark: the shared scenes from ``bench/scenes.py`` run in pymunk (C Chipmunk2D).

pymunk is used the idiomatic way: one ``pymunk.Space`` per world, default solver settings
(10 iterations, default collision slop and bias), sleeping left off (pymunk's default
``sleep_time_threshold`` is infinity) and no collision handlers in any timed loop.

How the scene parameters map onto pymunk (each checked by experiment against pymunk 7.3.1):

* Drag: Chipmunk scales velocities by ``damping ** dt`` every step, so ``damping`` is the
  fraction of velocity kept per second. ``damping = exp(-k)`` therefore reproduces
  ``v(t) = v0 * exp(-k t)`` exactly (measured: a free body keeps 0.4965853 of its speed
  after 120 steps of 1/120 s, and exp(-0.7) = 0.4965853).
* Restitution and friction: Chipmunk combines the two shapes' values by multiplying them
  (measured: elasticities 0.5 and 0.8 give a 0.4 head-on restitution). Rather than a
  collision handler (a Python callback per contact would distort the timing), each value
  is split across the two shape kinds so that every product is the scene's coefficient.

Run ``python bench/pymunk_peer.py`` for the table and the self-checks.
"""

from __future__ import annotations

import math
import time

import numpy as np
import pymunk

try:  # imported as part of the repo (``bench.pymunk_peer``) ...
    from bench.scenes import (
        PoolBreak,
        Pyramid,
        Rain,
        StaticBox,
        pool_break,
        pyramid,
        rain,
        validate,
    )
except ImportError:  # ... or run as a script, with bench/ on sys.path
    from scenes import PoolBreak, Pyramid, Rain, StaticBox, pool_break, pyramid, rain, validate

BALL, CUSHION = 1, 2  # collision types, only used by the untimed momentum diagnostic


def _box_vertices(box: StaticBox) -> list[tuple[float, float]]:
    """Corners of an axis-aligned static box, counter-clockwise, in world coordinates."""
    (cx, cy), (hx, hy) = box.center, box.half_extents
    return [(cx - hx, cy - hy), (cx + hx, cy - hy), (cx + hx, cy + hy), (cx - hx, cy + hy)]


def _pool_space(scene: PoolBreak) -> tuple[pymunk.Space, list[pymunk.Body]]:
    """Build one pymunk world of the pool break; returns the space and its balls in order."""
    space = pymunk.Space()  # iterations=10, default slop/bias, sleeping off
    space.gravity = scene.gravity
    space.damping = math.exp(-scene.linear_drag)

    # Ball-ball contacts multiply two ball elasticities and ball-cushion contacts multiply a
    # ball and a cushion elasticity: sqrt(0.95)^2 = 0.95 and sqrt(0.95) * 0.75/sqrt(0.95) = 0.75.
    e_ball = math.sqrt(scene.restitution_ball_ball)
    e_cushion = scene.restitution_ball_cushion / e_ball
    mu = math.sqrt(scene.friction)  # same split for friction (0.0 here anyway)

    for box in scene.cushions:
        shape = pymunk.Poly(space.static_body, _box_vertices(box))
        shape.elasticity, shape.friction, shape.collision_type = e_cushion, mu, CUSHION
        space.add(shape)

    moment = pymunk.moment_for_circle(scene.ball_mass, 0.0, scene.ball_radius)
    balls = []
    for p, v in zip(scene.positions, scene.velocities, strict=True):
        body = pymunk.Body(scene.ball_mass, moment)
        body.position = (float(p[0]), float(p[1]))
        body.velocity = (float(v[0]), float(v[1]))
        shape = pymunk.Circle(body, scene.ball_radius)
        shape.elasticity, shape.friction, shape.collision_type = e_ball, mu, BALL
        space.add(body, shape)
        balls.append(body)
    return space, balls


def _positions(bodies: list[pymunk.Body]) -> np.ndarray:
    """Centre positions of ``bodies`` as an (n, 2) array."""
    return np.array([tuple(b.position) for b in bodies], dtype=np.float64)


def _momentum(bodies: list[pymunk.Body]) -> np.ndarray:
    """Total linear momentum of ``bodies``."""
    return np.sum([np.multiply(b.mass, tuple(b.velocity)) for b in bodies], axis=0)


def _pool_momentum_check(scene: PoolBreak, steps: int) -> tuple[float, float, np.ndarray]:
    """Replay world 0 untimed and measure momentum conservation.

    Cushions are external forces, so momentum is only conserved until the first ball
    touches one; until then it must equal P0 * exp(-drag * t) exactly, whatever happens at
    the ball-ball contacts (including the break itself). Returns the largest relative
    deviation over that window, the window's length in seconds, and the final positions
    (to confirm the replay follows the timed run).
    """
    space, balls = _pool_space(scene)
    touched: list[bool] = []

    def on_cushion(arbiter: pymunk.Arbiter, space: pymunk.Space, data: object) -> None:
        touched.append(True)

    space.on_collision(BALL, CUSHION, begin=on_cushion)
    p0 = _momentum(balls)
    worst, window = 0.0, 0.0
    for k in range(1, steps + 1):
        space.step(scene.dt)
        if touched:  # an impulse from a cushion has been applied during this step
            break
        expected = p0 * math.exp(-scene.linear_drag * k * scene.dt)
        worst = max(worst, float(np.linalg.norm(_momentum(balls) - expected)))
        window = k * scene.dt
    for _ in range(k, steps):  # finish the replay for the determinism comparison
        space.step(scene.dt)
    return worst / float(np.linalg.norm(p0)), window, _positions(balls)


def _warm_up() -> None:
    """Exercise pymunk's code paths once so first-call costs don't land in a timing."""
    space, _ = _pool_space(pool_break())
    for _ in range(120):
        space.step(1 / 120)
    space, _ = _pyramid_space(pyramid(4), iterations=10)
    for _ in range(60):
        space.step(1 / 60)


def pool_break_pymunk(
    n_worlds: int = 1, steps: int = 1200, cue_y_offsets: np.ndarray | None = None
) -> dict:
    """Time ``n_worlds`` independent pymunk pool-break worlds for ``steps`` steps each.

    With ``cue_y_offsets`` (``n_worlds`` values, m; see :func:`scenes.pool_cue_offsets`)
    space ``i`` starts its cue ball at ``y = cue_y_offsets[i]``, i.e. it is
    ``pool_break(cue_y_offsets[i])``: every world plays its own shot.

    Returns ``world_steps_per_s`` (n_worlds * steps / seconds), ``seconds`` (wall time of
    the stepping only, building excluded), ``final_positions`` of world 0 (n_balls, 2) and
    ``momentum_error`` (see :func:`_pool_momentum_check`, measured on an untimed replay of
    world 0) plus ``momentum_window_s``, the time span that check covers.
    """
    if cue_y_offsets is None:
        scenes = [pool_break()] * n_worlds
    else:
        offsets = np.asarray(cue_y_offsets, dtype=np.float64)
        if offsets.shape != (n_worlds,):
            raise ValueError(f"cue_y_offsets must have shape ({n_worlds},), got {offsets.shape}")
        scenes = [pool_break(float(y)) for y in offsets]
    scene = scenes[0]
    for each in scenes[:1] if cue_y_offsets is None else scenes:
        validate(each)
    worlds = [_pool_space(each) for each in scenes]
    spaces = [space for space, _ in worlds]
    dt = scene.dt
    _warm_up()

    # World by world rather than step-major: each space's data stays hot in cache for its
    # whole run, which measured faster than sweeping all worlds every step.
    t0 = time.perf_counter()
    for space in spaces:
        step = space.step
        for _ in range(steps):
            step(dt)
    seconds = time.perf_counter() - t0

    final = _positions(worlds[0][1])
    error, window, replay = _pool_momentum_check(scene, steps)  # world 0's own scene
    if not np.array_equal(replay, final):
        raise RuntimeError("pymunk replay of world 0 diverged from the timed run")
    return {
        "world_steps_per_s": n_worlds * steps / seconds,
        "seconds": seconds,
        "final_positions": final,
        "momentum_error": error,
        "momentum_window_s": window,
    }


def _pyramid_space(scene: Pyramid, iterations: int) -> tuple[pymunk.Space, list[pymunk.Body]]:
    """Build the pyramid in pymunk; returns the space and its boxes in scene order."""
    space = pymunk.Space()  # default slop/bias, sleeping off
    space.iterations = iterations
    space.gravity = scene.gravity
    mu = math.sqrt(scene.friction)  # product of the two shapes' frictions = scene.friction
    e = math.sqrt(scene.restitution)

    ground = pymunk.Poly(space.static_body, _box_vertices(scene.ground))
    ground.friction, ground.elasticity = mu, e
    space.add(ground)

    size = (scene.box_size, scene.box_size)
    moment = pymunk.moment_for_box(scene.box_mass, size)
    boxes = []
    for p in scene.positions:
        body = pymunk.Body(scene.box_mass, moment)
        body.position = (float(p[0]), float(p[1]))
        shape = pymunk.Poly.create_box(body, size)  # radius 0: sharp corners
        shape.friction, shape.elasticity = mu, e
        space.add(body, shape)
        boxes.append(body)
    return space, boxes


def pyramid_pymunk(
    base: int, steps: int = 300, drift_steps: int = 600, *, iterations: int = 10
) -> dict:
    """Time the first ``steps`` steps of a pymunk box pyramid, then measure its drift.

    Stepping continues untimed up to ``drift_steps``; ``top_drift_m`` is how far the top
    box's centre has moved from its start, ``max_drift_m`` the largest such distance over
    all boxes. ``iterations`` defaults to pymunk's own default of 10.
    """
    scene = pyramid(base)
    validate(scene)
    space, boxes = _pyramid_space(scene, iterations)
    _warm_up()

    step, dt = space.step, scene.dt
    t0 = time.perf_counter()
    for _ in range(steps):
        step(dt)
    seconds = time.perf_counter() - t0
    for _ in range(steps, drift_steps):
        step(dt)

    drift = np.linalg.norm(_positions(boxes) - scene.positions, axis=1)
    return {
        "ms_per_step": 1000 * seconds / steps,
        "top_drift_m": float(drift[scene.top_index]),
        "max_drift_m": float(drift.max()),
    }


def _rain_space(scene: Rain, sleeping: bool = False) -> tuple[pymunk.Space, list[pymunk.Body]]:
    """Build the rain scene in pymunk; returns the space and its bodies in scene order.

    The ground is the scene's finite stand-in box (a static ``Poly``, top face at y = 0,
    50 m wider than the drop zone on each side) with the scene's friction split as
    sqrt(mu) on each side (Chipmunk multiplies them), as for the pyramid.
    """
    space = pymunk.Space()  # iterations=10, default slop/bias, sleeping off
    if sleeping:  # bodies idle for 0.5 s (Box2D's and impulse2d's default) fall asleep
        space.sleep_time_threshold = 0.5
    space.gravity = scene.gravity
    mu = math.sqrt(scene.friction)
    e = math.sqrt(scene.restitution)

    ground = pymunk.Poly(space.static_body, _box_vertices(scene.ground))
    ground.friction, ground.elasticity = mu, e
    space.add(ground)

    r, size = scene.circle_radius, scene.box_size
    circle_moment = pymunk.moment_for_circle(scene.mass, 0.0, r)
    box_moment = pymunk.moment_for_box(scene.mass, size)
    bodies = []
    for p, angle, is_circle in zip(scene.positions, scene.angles, scene.is_circle, strict=True):
        body = pymunk.Body(scene.mass, circle_moment if is_circle else box_moment)
        body.position = (float(p[0]), float(p[1]))
        body.angle = float(angle)
        shape = pymunk.Circle(body, r) if is_circle else pymunk.Poly.create_box(body, size)
        shape.friction, shape.elasticity = mu, e
        space.add(body, shape)
        bodies.append(body)
    return space, bodies


def _rain_ms(space: pymunk.Space, dt: float, steps: int, settle_steps: int) -> float:
    """ms a step over ``steps`` steps of ``space`` after ``settle_steps`` untimed ones."""
    _warm_up()
    for _ in range(settle_steps):
        space.step(dt)
    t0 = time.perf_counter()
    for _ in range(steps):
        space.step(dt)
    return 1000 * (time.perf_counter() - t0) / steps


def rain_pymunk(count: int, steps: int = 120, settle_steps: int = 60) -> dict:
    """Time ``steps`` steps of the pymunk rain scene after ``settle_steps`` untimed ones.

    Returns ``ms_per_step``, ``mean_y`` (mean height of the bodies' centres at the end, m)
    and ``finite``.
    """
    scene = rain(count)
    validate(scene)
    space, bodies = _rain_space(scene)
    ms = _rain_ms(space, scene.dt, steps, settle_steps)
    pos = _positions(bodies)
    return {
        "ms_per_step": ms,
        "mean_y": float(pos[:, 1].mean()),
        "finite": bool(np.all(np.isfinite(pos))),
    }


def settled_rain_pymunk(count: int, steps: int = 120, settle_steps: int = 600) -> dict:
    """The rain with sleeping on, as ``box2d_peer.settled_rain_box2d``: ``ms_per_step``
    after ``settle_steps`` untimed steps, and ``awake`` (bodies awake at the end)."""
    scene = rain(count)
    space, bodies = _rain_space(scene, sleeping=True)
    ms = _rain_ms(space, scene.dt, steps, settle_steps)
    return {"ms_per_step": ms, "awake": sum(not b.is_sleeping for b in bodies)}


def _self_check(result: dict, scene: PoolBreak) -> None:
    """Sanity checks on a pool-break result; raises AssertionError on failure."""
    # Ball-ball impulses are equal and opposite and drag scales every ball by the same
    # factor, so before any cushion contact only rounding error is allowed.
    assert result["momentum_error"] < 1e-9, result["momentum_error"]
    # The cue ball reaches the apex at t ~ 0.16 s; the window must include the break.
    assert result["momentum_window_s"] > 0.2, "the window should cover the break"
    final = result["final_positions"]
    half = np.array(scene.play_area) / 2
    # Chipmunk tolerates up to collision_slop (0.1) of penetration, so allow a little.
    assert np.all(np.abs(final) < half + scene.ball_radius), "a ball left the table"
    assert not np.array_equal(final[1:], scene.positions[1:]), "the rack never broke"


def main() -> None:
    """Print the peer benchmark table and run the self-checks."""
    t_start = time.perf_counter()
    scene = pool_break()
    validate(scene)  # raises ValueError on overlaps or balls off the table
    print(scene.describe())
    print(f"pymunk {pymunk.version} (Chipmunk {pymunk.chipmunk_version[:5]})\n")

    print(f"{'scene':<28}{'steps':>7}{'seconds':>9}{'world-steps/s':>15}{'momentum err':>14}")
    # One world runs in milliseconds, so report the median of several runs; the 1024-world
    # run is long enough (a few seconds) to time once.
    for n_worlds, repeats in ((1, 7), (1024, 1)):
        runs = [pool_break_pymunk(n_worlds, scene.steps) for _ in range(repeats)]
        for res in runs:
            _self_check(res, scene)
        res = sorted(runs, key=lambda r: r["seconds"])[repeats // 2]
        print(
            f"{f'pool break, {n_worlds} world(s)':<28}{scene.steps:>7}{res['seconds']:>9.3f}"
            f"{res['world_steps_per_s']:>15,.0f}{res['momentum_error']:>14.1e}"
        )

    print(f"\n{'scene':<28}{'ms/step':>9}{'top drift m':>13}{'max drift m':>13}")
    for base in (10, 20):
        res = pyramid_pymunk(base)
        print(
            f"{f'pyramid base {base}':<28}{res['ms_per_step']:>9.3f}"
            f"{res['top_drift_m']:>13.4f}{res['max_drift_m']:>13.4f}"
        )
    print(f"\nself-checks passed; total {time.perf_counter() - t_start:.1f} s")


if __name__ == "__main__":
    main()
