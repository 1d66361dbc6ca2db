"""Peer for the env benchmark: the Pool2D-v0 table and shot in pymunk (C Chipmunk2D).

The game of ``impulse2d.envs.pool``, with its constants imported so the two cannot drift
apart: 16 balls (the cue ball uniform behind the head string, clear of the rack and the
pockets, plus ``rack_positions()``), ``cushions()`` as static boxes, ``pockets()``. A shot
sets the cue ball moving (an impulse ``m v`` here, which pymunk takes and which wakes it),
the action mapped as ``PoolGame._launch`` maps it (angle ``pi a0``, speed linear on
``SPEED_RANGE``), then dt = 1/120 s steps until every
ball is at rest, or 20 s. A potted cue ball comes back near the head spot
(``PoolGame._spot_near_head``); after 30 shots or a cleared table the balls are racked.

Common to both models below (pymunk 7.3.1):

* One ``pymunk.Space`` per table, zero gravity, pymunk's defaults otherwise: 10 solver
  iterations, one step per dt (impulse2d's pool world takes 2 substeps; we keep pymunk's
  default rather than halve dt), default collision slop and bias.
* Chipmunk multiplies the two shapes' restitution and friction: the ball gets sqrt(0.95)
  and the cushion 0.75 / sqrt(0.95), so ball-ball is 0.95 and ball-cushion 0.75 (impulse2d
  mixes by min); friction: ball sqrt(0.06), cushion sqrt(0.2), impulse2d's sqrt mixing
  exactly. Chipmunk has no restitution threshold (impulse2d: 0.02 m/s).
* A ball whose centre enters a pocket circle is removed from the space, and, as
  impulse2d's safeguard does, so is one whose centre gets a radius past a cushion line (a
  fast ball can cross a pocket's circle between two steps). ``escaped`` counts those not
  near any pocket: a ball through a cushion, a physics failure.

Rolling resistance (a constant 0.1 m/s^2 deceleration), spin drag (``w`` decays as
``exp(-3 t)``) and "at rest" have no Chipmunk setting (``space.damping`` is exponential
and acts on both velocities). Two models:

``model="joints"`` (default; Chipmunk's own idiom for top-down friction, as in its Tank
demo): each ball has a ``PivotJoint`` to the static body at its centre, ``max_bias = 0``,
``max_force = m * 0.1 N``: it removes up to 0.1 m/s of speed per second and never reverses
it, exactly the constant deceleration; and a ``DampedRotarySpring`` (stiffness 0, damping
``3 I``), whose implicit damping multiplies ``w`` by ``exp(-3 dt)`` a step (both measured
exact to 1e-14). Pockets are sensor circles of radius ``pocket - r`` (a ball's shape
touches one exactly when its centre enters the pocket circle) plus sensor boxes past the
cushion lines; a ``begin`` callback removes the ball, so Python runs only when a ball
drops. "At rest" is Chipmunk's sleeping with impulse2d's values
(``sleep_time_threshold = 0.1`` s, ``idle_speed_threshold = 0.01`` m/s; Chipmunk's idle
test is ``sqrt(v^2 + w^2 r^2 / 2) < 0.01``, impulse2d's ``|vx| + |vy| + r |w| < 0.01``):
sleeping balls cost nothing, as in impulse2d, and the shot ends when all are asleep,
polled on one ball that was awake (one attribute read a step). A rack or respot puts the
balls to sleep (``Body.sleep``), as ``World.stop`` does.

``model="numpy"`` (the issue's suggestion; kept to show what a Python-side model costs):
every step reads the velocities of all tables (``pymunk.batch.get_space_bodies``, one call
per space into one shared buffer), applies ``v *= max(0, 1 - a dt / |v|)`` (impulse2d's
formula) and the spin decay in numpy over all balls of all tables at once, and writes them
back (``set_space_bodies``; a Python ``velocity_func`` would be a C-to-Python callback per
ball per step, slower still). That write goes through ``cpBodySetVelocity``, which wakes
every body, so Chipmunk's sleeping cannot be used: the same pass emulates it (a ball slow
by impulse2d's bound for 0.1 s is asleep, its velocity zeroed until something hits it)
and tests the pockets. Tables run in lockstep to share the pass; ``python_share`` is the
share of time outside ``space.step``.

In both models a table starts its next shot as soon as its own has ended: pymunk tables
never wait for each other, unlike a vector env's step, which waits for its slowest world.

``python bench/pymunk_pool_env.py`` runs the self-checks: constants against the env, no
ball through a cushion, mean physics steps per shot against ``info["physics_steps"]``.
"""

from __future__ import annotations

import math
import multiprocessing as mp
import queue
import time
from collections.abc import Callable
from typing import Any

import numpy as np
import pymunk
import pymunk.batch as pb

from impulse2d.envs import pool
from impulse2d.envs._core import action_to_range
from impulse2d.envs.pool import BALL_MASS, BALL_RADIUS, DT, PoolGame

# PoolGame's world settings and episode limits, not importable (checked by check_constants).
SLEEP_SPEED = 0.01  # m/s
TIME_TO_SLEEP = 0.1  # s
MAX_SHOT_STEPS = round(20.0 / DT)  # max_shot_seconds = 20
MAX_EPISODE_SHOTS = 30  # Pool2D-v0's max_episode_steps
BALLS = 16  # cue ball (slot 0) + 15 object balls
SLOTS = BALLS + 1  # numpy model: rows of a table's timers, the balls and the static body
MODELS = ("joints", "numpy")

BALL, POCKET, OUTSIDE = 1, 2, 3  # collision types (joints model)
_GET = pb.BodyFields.POSITION | pb.BodyFields.VELOCITY | pb.BodyFields.ANGULAR_VELOCITY
_SET = pb.BodyFields.VELOCITY | pb.BodyFields.ANGULAR_VELOCITY
_ROLL_DV = pool.ROLLING_RESISTANCE * DT  # speed taken off per step (m/s)
_SPIN_KEEP = math.exp(-pool.SPIN_DRAG * DT)  # angular velocity kept per step
_HALF_L, _HALF_W = pool.TABLE_LENGTH / 2, pool.TABLE_WIDTH / 2
_POCKET_C, _POCKET_R = pool.pockets()


def _near_pocket(x: float, y: float) -> bool:
    """Within 10 cm of a pocket circle: a ball out here went down a pocket's mouth."""
    d = np.hypot(_POCKET_C[:, 0] - x, _POCKET_C[:, 1] - y)
    return bool(np.any(d < _POCKET_R + 0.1))


def _box(x0: float, y0: float, x1: float, y1: float) -> list[tuple[float, float]]:
    return [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]


class Table:
    """One pool table in its own ``pymunk.Space``, with the game's bookkeeping."""

    def __init__(self, rng: np.random.Generator, model: str = "joints") -> None:
        if model not in MODELS:
            raise ValueError(f"model must be one of {MODELS}, got {model!r}")
        self.rng, self.model = rng, model
        self.space = space = pymunk.Space()
        space.gravity = (0.0, 0.0)
        static = space.static_body
        e_ball = math.sqrt(pool.RESTITUTION_BALL)
        for x, y, w, h in pool.cushions():
            shape = pymunk.Poly(static, _box(x - w / 2, y - h / 2, x + w / 2, y + h / 2))
            shape.elasticity = pool.RESTITUTION_CUSHION / e_ball
            shape.friction = math.sqrt(pool.FRICTION_CUSHION)
            space.add(shape)
        moment = pymunk.moment_for_circle(BALL_MASS, 0.0, BALL_RADIUS)
        self.parts: list[tuple[Any, ...]] = []  # per ball: everything to add and remove
        for _ in range(BALLS):
            body = pymunk.Body(BALL_MASS, moment)
            shape = pymunk.Circle(body, BALL_RADIUS)
            shape.elasticity, shape.friction = e_ball, math.sqrt(pool.FRICTION_BALL)
            shape.collision_type = BALL
            parts: tuple[Any, ...] = (body, shape)
            if model == "joints":
                roll = pymunk.PivotJoint(static, body, (0.0, 0.0), (0.0, 0.0))
                roll.max_bias, roll.max_force = 0.0, BALL_MASS * pool.ROLLING_RESISTANCE
                spin = pymunk.DampedRotarySpring(static, body, 0.0, 0.0, pool.SPIN_DRAG * moment)
                parts += (roll, spin)
            self.parts.append(parts)
        self.bodies: list[pymunk.Body] = [p[0] for p in self.parts]
        self.slot_of = {body.id: k for k, body in enumerate(self.bodies)}
        self.slot_of[static.id] = BALLS
        if model == "joints":
            space.sleep_time_threshold = TIME_TO_SLEEP
            space.idle_speed_threshold = SLEEP_SPEED
            self._add_sensors()
        self.potted = np.ones(BALLS, dtype=bool)  # nothing in the space yet
        self.escaped = 0
        self.shots = 0  # in this episode
        self.pots_before = 0
        self.rack()

    def _add_sensors(self) -> None:
        """Pocket circles shrunk by a ball radius, and boxes whose inner faces are two radii
        past the cushion lines: a ball's shape touches one exactly when its centre is
        inside the pocket circle or a radius past the line, impulse2d's tests."""
        static, r = self.space.static_body, BALL_RADIUS
        sensors = [
            pymunk.Circle(static, radius - r, (float(c[0]), float(c[1])))
            for c, radius in zip(_POCKET_C, _POCKET_R, strict=True)
        ]
        lx, ly, far = _HALF_L + 2 * r, _HALF_W + 2 * r, 1.0
        for x0, y0, x1, y1 in (
            (lx, -ly - far, lx + far, ly + far),
            (-lx - far, -ly - far, -lx, ly + far),
            (-lx - far, ly, lx + far, ly + far),
            (-lx - far, -ly - far, lx + far, -ly),
        ):
            sensors.append(pymunk.Poly(static, _box(x0, y0, x1, y1)))
        for shape in sensors:
            shape.sensor = True
            shape.collision_type = POCKET if isinstance(shape, pymunk.Circle) else OUTSIDE
        self.space.add(*sensors)
        self.space.on_collision(BALL, POCKET, begin=self._dropped)
        self.space.on_collision(BALL, OUTSIDE, begin=self._dropped)

    def _dropped(self, arbiter: pymunk.Arbiter, space: pymunk.Space, data: Any) -> None:
        ball, sensor = arbiter.shapes
        slot = self.slot_of[ball.body.id]
        if self.potted[slot]:  # touching two sensors at once: removed already
            return
        if sensor.collision_type == OUTSIDE and not _near_pocket(*ball.body.position):
            self.escaped += 1
        self.pot(slot)  # pymunk defers the removal to the end of the step

    def rack(self) -> None:
        """A new episode: every ball back in the space, in the rack, at rest."""
        placed = list(pool.rack_positions())
        positions = [_cue_spot(self.rng, placed), *placed]
        for k, (body, p) in enumerate(zip(self.bodies, positions, strict=True)):
            if self.potted[k]:
                self.space.add(*self.parts[k])
            body.position = (float(p[0]), float(p[1]))
            body.velocity, body.angular_velocity, body.angle = (0.0, 0.0), 0.0, 0.0
        self.potted[:] = False
        self.shots = 0
        self.sleep()

    def sleep(self) -> None:
        """Every ball at rest and (joints model) asleep: ``World.stop``."""
        for k in np.flatnonzero(~self.potted):
            body = self.bodies[k]
            body.velocity, body.angular_velocity = (0.0, 0.0), 0.0
            if self.model == "joints":
                body.sleep()

    def pot(self, slot: int) -> None:
        self.space.remove(*self.parts[slot])
        self.potted[slot] = True

    def respot_cue(self) -> None:
        """The env's rule: the cue ball back on the head spot, or the nearest free point."""
        live = [tuple(self.bodies[k].position) for k in range(1, BALLS) if not self.potted[k]]
        spot = PoolGame._spot_near_head(np.array(live).reshape(-1, 2))
        cue = self.bodies[0]
        self.space.add(*self.parts[0])
        cue.position = (float(spot[0]), float(spot[1]))
        cue.velocity, cue.angular_velocity = (0.0, 0.0), 0.0
        self.potted[0] = False
        if self.model == "joints":
            cue.sleep()

    def launch(self) -> None:
        """A random action in [-1, 1]^2, mapped exactly as ``PoolGame._launch`` maps it."""
        a = self.rng.uniform(-1.0, 1.0, 2)
        angle, speed = math.pi * a[0], action_to_range(a[1], pool.SPEED_RANGE)
        cue = self.bodies[0]
        impulse = (BALL_MASS * speed * math.cos(angle), BALL_MASS * speed * math.sin(angle))
        cue.apply_impulse_at_world_point(impulse, cue.position)  # wakes it
        self.pots_before = int(self.potted[1:].sum())
        self.shots += 1

    def end_shot(self) -> bool:
        """``PoolGame._score``'s bookkeeping after a shot; returns whether it potted an
        object ball. Respots a potted cue ball and racks when the episode is over."""
        potted = int(self.potted[1:].sum()) > self.pots_before
        if self.potted[0]:
            self.respot_cue()
        if self.potted[1:].all() or self.shots >= MAX_EPISODE_SHOTS:
            self.rack()
        return potted

    def slots_in_order(self, ids: pb.Buffer) -> np.ndarray:
        """Ball slot of each row that the batch calls return for this space (their order is
        the space's body array, which a removal reshuffles); the static body is ``BALLS``."""
        ids.clear()
        pb.get_space_bodies(self.space, pb.BodyFields.BODY_ID, ids)
        raw = np.frombuffer(ids.int_buf(), dtype=np.uintp)
        return np.array([self.slot_of[int(i)] for i in raw], dtype=np.int64)


def _cue_spot(rng: np.random.Generator, placed: list) -> np.ndarray:
    """``PoolGame._free_spot`` for the cue ball: uniform behind the head string, 1 mm clear
    of the rack and clear of the pockets."""
    r = BALL_RADIUS
    half_l, half_w = _HALF_L - 2 * r, _HALF_W - 2 * r
    others = np.array(placed).reshape(-1, 2)
    while True:
        point = np.array([rng.uniform(-half_l, pool.HEAD_SPOT[0]), rng.uniform(-half_w, half_w)])
        clear = np.all(np.hypot(*(others - point).T) > 2 * r + 1e-3)
        if clear and np.all(np.hypot(*(_POCKET_C - point).T) > _POCKET_R + 2 * r):
            return point


class _Runner:
    """Plays shots on a set of tables, from the first shot it launches on each, and records
    them (subclasses: the two models)."""

    def __init__(self, tables: list[Table]) -> None:
        self.tables = tables
        self.reset()
        for table in tables:
            table.launch()

    def reset(self) -> None:
        self.shot_steps: list[int] = []
        self.shot_pots: list[bool] = []
        self.step_seconds = 0.0  # numpy model only: time in space.step
        for table in self.tables:
            table.escaped = 0

    def run(self, shots: int, progress: Callable[[int], None] | None = None) -> None:
        raise NotImplementedError


class _JointRunner(_Runner):
    """Joints model: each shot runs to rest in C; tables take turns shot by shot."""

    def __init__(self, tables: list[Table]) -> None:
        super().__init__(tables)
        self.turn = 0

    def run(self, shots: int, progress: Callable[[int], None] | None = None) -> None:
        for _ in range(shots):
            table = self.tables[self.turn]
            self.turn = (self.turn + 1) % len(self.tables)
            step, bodies, potted = table.space.step, table.bodies, table.potted
            watch, steps = 0, 0  # the cue ball is awake: the shot has just been launched
            while steps < MAX_SHOT_STEPS:
                step(DT)
                steps += 1
                if potted[watch] or bodies[watch].is_sleeping:
                    # The watched ball stopped: find another that still moves, if any.
                    awake = [k for k in range(BALLS) if not potted[k] and not bodies[k].is_sleeping]
                    if not awake:
                        break
                    watch = awake[0]
            else:
                table.sleep()  # the cap: end the shot where it stands
            self.shot_steps.append(steps)
            self.shot_pots.append(table.end_shot())
            table.launch()
            if progress is not None:
                progress(1)


class _NumpyRunner(_Runner):
    """Numpy model: tables in lockstep, one vectorised velocity pass a step for all."""

    def __init__(self, tables: list[Table]) -> None:
        super().__init__(tables)
        self.timers = np.full((len(tables), SLOTS), TIME_TO_SLEEP)  # slow time per ball
        self.steps = np.zeros(len(tables), np.int64)  # physics steps of each table's shot
        self.read, self.write, self.ids = pb.Buffer(), pb.Buffer(), pb.Buffer()
        self.dirty = set(range(len(tables)))  # tables whose row order must be re-read
        self.slots: list[np.ndarray] = [np.zeros(0, np.int64)] * len(tables)

    def _layout(self) -> None:
        """Row bookkeeping after bodies were added or removed: each row's timer index and
        table, and each table's first row."""
        for k in self.dirty:
            self.slots[k] = self.tables[k].slots_in_order(self.ids)
        self.dirty.clear()
        counts = np.array([s.size for s in self.slots])
        self.bounds = np.concatenate([[0], np.cumsum(counts)])
        self.row_table = np.repeat(np.arange(len(self.tables)), counts)
        self.row_key = self.row_table * SLOTS + np.concatenate(self.slots)

    def run(self, shots: int, progress: Callable[[int], None] | None = None) -> None:
        tables, timers = self.tables, self.timers.reshape(-1)
        read, write = self.read, self.write
        clock = time.perf_counter
        done, goal = len(self.shot_steps), len(self.shot_steps) + shots
        while done < goal:
            if self.dirty:
                self._layout()
            t = clock()
            for table in tables:
                table.space.step(DT)
            self.step_seconds += clock() - t

            read.clear()  # one buffer for all spaces: each get appends its rows
            for table in tables:
                pb.get_space_bodies(table.space, _GET, read)
            data = np.frombuffer(read.float_buf()).reshape(-1, 5)  # x, y, vx, vy, w
            vx, vy, w = data[:, 2], data[:, 3], data[:, 4]
            keep = np.maximum(1.0 - _ROLL_DV / np.maximum(np.hypot(vx, vy), 1e-300), 0.0)
            vel = np.empty((data.shape[0], 3))
            np.multiply(vx, keep, out=vel[:, 0])
            np.multiply(vy, keep, out=vel[:, 1])
            np.multiply(w, _SPIN_KEEP, out=vel[:, 2])
            bound = np.abs(vel[:, 0]) + np.abs(vel[:, 1]) + BALL_RADIUS * np.abs(vel[:, 2])
            key = self.row_key
            slow_for = np.where(bound < SLEEP_SPEED, timers[key] + DT, 0.0)
            timers[key] = slow_for
            vel[slow_for >= TIME_TO_SLEEP] = 0.0  # asleep: stays put until hit
            bounds = self.bounds
            for k, table in enumerate(tables):  # before any removal: rows still in order
                write.set_float_buf(vel[bounds[k] : bounds[k + 1]])
                pb.set_space_bodies(table.space, _SET, write)

            x, y = data[:, 0], data[:, 1]
            dx = x[:, None] - _POCKET_C[:, 0]
            dy = y[:, None] - _POCKET_C[:, 1]
            pocketed = (dx * dx + dy * dy < _POCKET_R**2).any(axis=1)
            out = (np.abs(x) > _HALF_L + BALL_RADIUS) | (np.abs(y) > _HALF_W + BALL_RADIUS)
            if (pocketed | out).any():
                self._pot(np.flatnonzero(pocketed | out), pocketed, data)

            self.steps += 1
            ended = (self.timers >= TIME_TO_SLEEP).all(axis=1) | (self.steps >= MAX_SHOT_STEPS)
            if ended.any():
                ended = np.flatnonzero(ended)
                for k in ended:
                    self._next_shot(int(k))
                finished = min(ended.size, goal - done)
                done += finished
                if progress is not None:
                    progress(finished)

    def _pot(self, rows: np.ndarray, pocketed: np.ndarray, data: np.ndarray) -> None:
        for row in rows:
            k, slot = int(self.row_table[row]), int(self.row_key[row] % SLOTS)
            if slot == BALLS:  # the static body sits at the origin: never potted
                continue
            table = self.tables[k]
            if not pocketed[row] and not _near_pocket(data[row, 0], data[row, 1]):
                table.escaped += 1
            table.pot(slot)
            self.timers[k, slot] = TIME_TO_SLEEP  # gone: never holds the shot open
            self.dirty.add(k)

    def _next_shot(self, k: int) -> None:
        table = self.tables[k]
        if self.steps[k] >= MAX_SHOT_STEPS:
            table.sleep()
        self.shot_steps.append(int(self.steps[k]))
        before = table.potted.copy()
        self.shot_pots.append(table.end_shot())
        if not np.array_equal(before, table.potted):
            self.dirty.add(k)
        self.timers[k] = TIME_TO_SLEEP  # every ball at rest: the stroke wakes the cue ball
        self.steps[k] = 0
        table.launch()


def play_shots(
    shots: int,
    tables: int = 32,
    seed: int = 0,
    *,
    model: str = "joints",
    warmup_shots: int | None = None,
    progress: Callable[[int], None] | None = None,
    start: Callable[[], None] | None = None,
) -> dict[str, Any]:
    """Play ``shots`` random shots, timed, on ``tables`` pymunk tables in one process.

    ``warmup_shots`` (default: two per table) are played first, untimed, on the same
    tables, so the timing is of the steady state (tables mid-episode, not all at the
    break). In the numpy model, shots in flight when the clock starts and stops count when
    they finish, as in any throughput measurement. ``progress(n)`` is called as timed shots
    finish; ``start()`` just before the clock starts (the parallel version's barrier).

    Returns ``shots``, ``seconds``, ``shots_per_s``, ``t0``/``t1`` (``perf_counter`` at
    the start and end), ``steps`` (physics steps of every timed shot), ``pots`` (whether
    each potted an object ball), ``mean_steps``, ``pot_fraction``, ``capped`` (shots
    stopped by the 20 s cap), ``escaped`` (balls found past a cushion line away from every
    pocket) and ``python_share`` (numpy model: share of the time outside ``space.step``;
    else None).
    """
    seeds = np.random.SeedSequence(seed).spawn(tables)
    tabs = [Table(np.random.default_rng(s), model) for s in seeds]
    runner = (_JointRunner if model == "joints" else _NumpyRunner)(tabs)
    runner.run(2 * tables if warmup_shots is None else warmup_shots)
    runner.reset()
    if start is not None:
        start()
    t0 = time.perf_counter()
    runner.run(shots, progress)
    t1 = time.perf_counter()
    share = 1.0 - runner.step_seconds / (t1 - t0) if model == "numpy" else None
    escaped = sum(t.escaped for t in tabs)
    return _result(t0, t1, runner.shot_steps[:shots], runner.shot_pots[:shots], escaped, share)


def _result(
    t0: float, t1: float, steps: list, pots: list, escaped: int, share: float | None
) -> dict[str, Any]:
    steps_a = np.asarray(steps)
    return {
        "shots": steps_a.size,
        "seconds": t1 - t0,
        "shots_per_s": steps_a.size / (t1 - t0),
        "t0": t0,
        "t1": t1,
        "steps": steps_a,
        "pots": np.asarray(pots),
        "mean_steps": float(steps_a.mean()),
        "pot_fraction": float(np.mean(pots)),
        "capped": int(np.sum(steps_a >= MAX_SHOT_STEPS)),
        "escaped": escaped,
        "python_share": share,
    }


# -- several processes -------------------------------------------------------------------------
def _worker(index: int, kwargs: dict, barrier: Any, counters: Any, results: Any) -> None:
    def progress(n: int) -> None:
        counters[index] += n  # each worker writes only its own slot: no lock needed

    res = play_shots(**kwargs, progress=progress, start=barrier.wait)
    res["steps"], res["pots"] = res["steps"].tolist(), res["pots"].tolist()
    results.put(res)


def play_shots_parallel(
    shots: int,
    processes: int = 2,
    tables: int = 32,
    seed: int = 0,
    *,
    model: str = "joints",
    progress: Callable[[int], None] | None = None,
) -> dict[str, Any]:
    """:func:`play_shots` in ``processes`` worker processes (spawned, so nothing is
    inherited), each playing its share of ``shots`` on its own ``tables`` tables.

    The workers build and warm up their tables, meet at a barrier, then run; the aggregate
    rate is all shots over the span from the earliest start to the latest finish (both
    ``perf_counter``: CLOCK_MONOTONIC on Linux, one clock for all processes). Returns the
    keys of :func:`play_shots` (``steps`` of all workers) plus ``per_process`` (shots/s).
    """
    ctx = mp.get_context("spawn")
    barrier = ctx.Barrier(processes)
    counters = ctx.Array("q", processes, lock=False)
    results = ctx.Queue()
    workers = []
    for i in range(processes):
        kwargs = {
            "shots": shots // processes + (i < shots % processes),
            "tables": tables,
            "seed": seed + 1000 * (i + 1),
            "model": model,
        }
        workers.append(
            ctx.Process(target=_worker, args=(i, kwargs, barrier, counters, results), daemon=True)
        )
    for p in workers:
        p.start()
    outs: list[dict] = []
    reported = 0
    while len(outs) < processes:
        try:
            outs.append(results.get(timeout=0.2))
        except queue.Empty:
            if not any(p.is_alive() for p in workers) and results.empty():
                raise RuntimeError("a pymunk worker died") from None
        now = sum(counters)
        if progress is not None and now > reported:
            progress(now - reported)
            reported = now
    for p in workers:
        p.join()
    t0, t1 = min(o["t0"] for o in outs), max(o["t1"] for o in outs)
    steps, pots = [s for o in outs for s in o["steps"]], [p for o in outs for p in o["pots"]]
    shares = [o["python_share"] for o in outs]
    share = None if None in shares else float(np.mean(shares))
    res = _result(t0, t1, steps, pots, sum(o["escaped"] for o in outs), share)
    res["per_process"] = [o["shots_per_s"] for o in outs]
    return res


# -- self-checks -------------------------------------------------------------------------------
def check_constants() -> None:
    """The values copied from the env's code (not importable) still match it."""
    import gymnasium as gym

    import impulse2d  # noqa: F401  (registers Pool2D-v0)

    game = PoolGame(1)
    assert game.world.sleep_speed == SLEEP_SPEED, game.world.sleep_speed
    assert game.world.time_to_sleep == TIME_TO_SLEEP, game.world.time_to_sleep
    assert game.max_shot_steps == MAX_SHOT_STEPS, game.max_shot_steps
    assert gym.spec("Pool2D-v0").max_episode_steps == MAX_EPISODE_SHOTS


def check_result(res: dict[str, Any]) -> None:
    """Physics sanity of a run; raises AssertionError on failure."""
    assert res["escaped"] == 0, f"{res['escaped']} balls left the table through a cushion"
    assert 1 <= res["mean_steps"] <= MAX_SHOT_STEPS, res["mean_steps"]
    assert np.all(res["steps"] >= 1), "a shot ended before it started"


def main() -> None:
    """Self-checks and a short comparison of steps per shot with impulse2d."""
    import gymnasium as gym

    check_constants()
    print(f"pymunk {pymunk.version}: constants match PoolGame")
    env = gym.make_vec("Pool2D-v0", num_envs=64, vectorization_mode="vector_entry_point")
    env.reset(seed=0)
    env.action_space.seed(0)
    steps, pots = [], []
    for _ in range(4):
        *_, info = env.step(env.action_space.sample())
        steps.append(info["physics_steps"])
        pots.append(info["potted"] > 0)
    mean = float(np.mean(steps))
    print(
        f"impulse2d, 64 worlds x 4 shots: {mean:.0f} steps/shot, pots {100 * np.mean(pots):.0f} %"
    )
    for model in MODELS:
        for procs in (1, 2):
            one = procs == 1
            res = play_shots(600, model=model) if one else play_shots_parallel(600, model=model)
            check_result(res)
            share = res["python_share"]
            print(
                f"pymunk {model}, {procs} process(es): {res['shots_per_s']:.1f} shots/s, "
                f"{res['mean_steps']:.0f} steps/shot, pots {100 * res['pot_fraction']:.0f} %, "
                f"capped {res['capped']}"
                + ("" if share is None else f", python share {100 * share:.0f} %")
            )
            ratio = res["mean_steps"] / mean
            assert 0.67 < ratio < 1.5, f"steps per shot differ by x{ratio:.2f}: not the same shots"
    print("self-checks passed")


if __name__ == "__main__":
    main()
