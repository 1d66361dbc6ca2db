"""The World: settings, and the step pipeline that advances every world of the batch.

``World.step`` reads top to bottom as the pipeline it is (Box2D v3's soft step):

    broadphase -> narrowphase (a function per shape pair) -> wake touched islands ->
    body terms (gravity, forces, drag) -> contact constraints (warm start, colours) ->
    substeps [integrate velocities -> warm start -> solve -> integrate positions -> relax]
    -> restitution -> store impulses, clear forces, sleep

Every stage works on whole arrays: the flat index of a body is ``world * N + slot``
(see ``state.py``), and a single world is simply a batch of one.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from . import _checks, solver
from . import springs as spring_forces
from ._slots import SlotStore
from ._snapshot import SnapshotMixin
from .broadphase import split_keys
from .contacts import MIXING_RULES, Cache, Contacts, build, point_keys, soft_constraint
from .energy import Energy, energy_of
from .narrowphase import COLLIDE, FEATURES, PAIR_SHAPES, Points, Shapes
from .sleep import fall_asleep
from .state import BOX, CIRCLE, PLANE

_LOCAL_RADIX = 1 << 20  # slots per world in a capacity-independent local key


class World(SlotStore, SnapshotMixin):
    """A 2D physics world, or a batch of ``batch_size`` worlds stepped together.

    Arguments (SI units):

    * ``gravity`` (m/s^2): settable; zero for a top-down table.
    * ``batch_size``: number of worlds. Every object added is added to all of them; its
      properties then read and write one value per world.
    * ``substeps``: solver substeps per ``step`` (Box2D v3 uses 4). More substeps make
      stacks stiffer and springs more accurate; cost grows linearly.
    * ``restitution_mixing`` / ``friction_mixing``: how a contact combines the two
      shapes' values: ``'max'``, ``'min'``, ``'mean'``, ``'product'`` or ``'sqrt'``
      (``sqrt(a b)``). Defaults are Box2D's (max, sqrt). A pool table uses
      ``restitution_mixing='min'``: balls 0.95 and cushions 0.75 give ball-ball 0.95 and
      ball-cushion 0.75.
    * ``restitution_threshold`` (m/s): slower impacts do not bounce (stops resting
      contacts from jittering). Box2D uses 1 m/s for metre-sized bodies.
    * ``contact_hertz``, ``contact_damping_ratio``: stiffness of the soft position
      correction of overlaps (capped at a quarter of the substep rate; twice as stiff
      against immovable bodies). ``contact_push_speed`` (m/s) caps how fast overlapping
      bodies are pushed apart, so a heavily overlapping start does not explode.
    * ``speculative_distance`` (m): contacts are made this much before shapes touch, on
      top of how far the pair can close in the step.
    * ``sleeping``: let islands of slow bodies sleep (``time_to_sleep`` s below
      ``sleep_speed`` m/s). Sleeping bodies cost nothing until something touches them.
    """

    def __init__(
        self,
        gravity: Any = (0.0, -9.81),
        *,
        batch_size: int = 1,
        substeps: int = 4,
        restitution_mixing: str = "max",
        friction_mixing: str = "sqrt",
        restitution_threshold: float = 1.0,
        contact_hertz: float = 30.0,
        contact_damping_ratio: float = 10.0,
        contact_push_speed: float = 3.0,
        speculative_distance: float = 0.02,
        sleeping: bool = True,
        time_to_sleep: float = 0.5,
        sleep_speed: float = 0.05,
    ) -> None:
        self._cache = Cache.empty()
        self._init_slots(_checks.positive_int("batch_size", batch_size))
        self.gravity = gravity
        self.substeps = substeps
        self._rules = (
            _checks.choice("restitution_mixing", restitution_mixing, MIXING_RULES),
            _checks.choice("friction_mixing", friction_mixing, MIXING_RULES),
        )
        self.restitution_threshold = _checks.non_negative(
            "restitution_threshold", restitution_threshold
        )
        self.contact_hertz = _checks.positive("contact_hertz", contact_hertz)
        self.contact_damping_ratio = _checks.non_negative(
            "contact_damping_ratio", contact_damping_ratio
        )
        self.contact_push_speed = _checks.positive("contact_push_speed", contact_push_speed)
        self.speculative_distance = _checks.non_negative(
            "speculative_distance", speculative_distance
        )
        if not isinstance(sleeping, (bool, np.bool_)):
            raise ValueError(f"sleeping must be a bool, got {sleeping!r}")
        self.sleeping = bool(sleeping)
        self.time_to_sleep = _checks.positive("time_to_sleep", time_to_sleep)
        self.sleep_speed = _checks.non_negative("sleep_speed", sleep_speed)
        self._time = np.zeros(self._batch)
        self.steps = 0
        self.last_contacts: Contacts | None = None

    # -- settings --------------------------------------------------------------------------
    @property
    def gravity(self) -> np.ndarray:
        """Gravitational acceleration (m/s^2), shape (2,). Setting it wakes every body."""
        return self._gravity.copy()

    @gravity.setter
    def gravity(self, value: Any) -> None:
        self._gravity = _checks.vector2("gravity", value)
        b = self._bodies
        b["awake"][...] |= b["enabled"] & (self._dynamic_flat.reshape(b["awake"].shape))
        b["sleep_time"][...] = 0.0

    @property
    def substeps(self) -> int:
        """Solver substeps per step."""
        return self._substeps

    @substeps.setter
    def substeps(self, value: int) -> None:
        self._substeps = _checks.positive_int("substeps", value)

    @property
    def restitution_mixing(self) -> str:
        return self._rules[0]

    @property
    def friction_mixing(self) -> str:
        return self._rules[1]

    @property
    def time(self) -> Any:
        """Simulated time (s): a float, or one per world."""
        return float(self._time[0]) if self._batch == 1 else self._time.copy()

    # -- the pipeline ----------------------------------------------------------------------
    def step(self, dt: float) -> None:
        """Advance every world by ``dt`` seconds (``substeps`` solver substeps inside)."""
        dt = _checks.positive("dt", dt)
        h = dt / self._substeps
        flat = self._flat()
        springs = self._active_springs(flat)
        speed = self._speed_bound(flat)
        keys, body_a, body_b = self._candidate_pairs(flat, speed, dt)
        points = self._narrowphase(flat, keys, body_a, body_b, speed, dt)
        self._wake_touched(flat, body_a[points.pair], body_b[points.pair], springs)
        movable, accel, damping, moving = self._body_terms(flat, h)
        if springs is not None:
            spring_forces.check_stable(
                flat["pose"],
                *self._spring_inverse(flat, movable),
                springs[0],
                springs[1],
                springs[2],
                h,
            )
        contacts = self._contacts(flat, movable, accel, points, keys, body_a, body_b, h)
        indices = solver.colour_indices(contacts)
        vel, pose = flat["vel"], flat["pose"]
        delta_pose = np.zeros_like(pose)
        separation = contacts.base_separation
        for _ in range(self._substeps):
            vel *= damping  # integrate velocities: drag, then gravity and forces
            vel += h * accel
            if springs is not None:
                self._apply_springs(flat, movable, springs, h)
            solver.warm_start(contacts, vel)
            solver.solve(contacts, indices, vel, separation, 1.0 / h, True, self.contact_push_speed)
            travel = h * vel * moving  # integrate positions
            pose += travel
            delta_pose += travel
            separation = solver.separation(contacts, delta_pose)
            solver.solve(
                contacts, indices, vel, separation, 1.0 / h, False, self.contact_push_speed
            )
        solver.restitution(contacts, vel, self.restitution_threshold, h)
        self._finish(flat, movable, contacts, springs, dt)

    # -- pipeline stages ----------------------------------------------------------------------
    def _flat(self) -> dict[str, np.ndarray]:
        b = self._bodies
        return {field.name: b.flat(field.name) for field in b.fields}

    def _speed_bound(self, flat: dict[str, np.ndarray]) -> np.ndarray:
        """An upper bound on how fast any point of each body moves (m/s)."""
        vel = flat["vel"]
        speed = np.abs(vel[0]) + np.abs(vel[1]) + np.abs(vel[2]) * flat["bound"]
        return np.where(flat["awake"], speed, 0.0)

    def _candidate_pairs(
        self, flat: dict[str, np.ndarray], speed: np.ndarray, dt: float
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Broadphase pairs plus body-plane pairs, those with something awake in them."""
        reach = speed * dt
        tight = flat["bound"] + 0.5 * self.speculative_distance + reach
        # The fat margin: a quarter of the body's size plus two steps of travel, so a body
        # crossing its own size takes a few steps and a resting one never re-queries.
        margin = 0.25 * flat["bound"] + 2.0 * reach
        enabled, awake = flat["enabled"], flat["awake"]
        keys, body_a, body_b = self._broadphase.update(
            flat["pose"][0],
            flat["pose"][1],
            tight,
            margin,
            awake & enabled,
            enabled & self._solid_flat,
            self._allowed,
            self._kind,
        )
        if self._plane_keys.size:
            keys = np.concatenate([keys, self._plane_keys])
            body_a = np.concatenate([body_a, self._plane_a])
            body_b = np.concatenate([body_b, self._plane_b])
        live = enabled[body_a] & enabled[body_b] & (awake[body_a] | awake[body_b])
        if live.all():
            return keys, body_a, body_b
        return keys[live], body_a[live], body_b[live]

    def _narrowphase(
        self,
        flat: dict[str, np.ndarray],
        keys: np.ndarray,
        body_a: np.ndarray,
        body_b: np.ndarray,
        speed: np.ndarray,
        dt: float,
    ) -> Points:
        """Contact points of every candidate pair, by the table in ``narrowphase.COLLIDE``."""
        n = self._bodies.capacity
        kind_span = self._batch * n * n  # keys of one pair kind lie in [k span, (k+1) span)
        edges = np.searchsorted(keys, np.arange(6) * kind_span)
        margin = self.speculative_distance + (speed[body_a] + speed[body_b]) * dt
        parts = []
        for pair_kind, collide in COLLIDE.items():
            lo, hi = edges[pair_kind], edges[pair_kind + 1]
            if lo == hi:
                continue
            a, b = body_a[lo:hi], body_b[lo:hi]
            kind_a, kind_b = PAIR_SHAPES[pair_kind]
            tag = ((a % n) * 65537 + b % n).astype(np.float64)
            found = collide(
                self._shapes(flat, kind_a, a), self._shapes(flat, kind_b, b), margin[lo:hi], tag
            )
            found.pair += lo
            parts.append(found)
        if not parts:
            empty = np.zeros(0)
            return Points(np.zeros(0, np.int64), *([empty] * 7), np.zeros(0, np.int64))
        return parts[0] if len(parts) == 1 else Points.concatenate(parts)

    @staticmethod
    def _shapes(flat: dict[str, np.ndarray], kind: int, index: np.ndarray) -> Shapes:
        pose = flat["pose"]
        shapes = Shapes(pose[0, index], pose[1, index])
        if kind == CIRCLE:
            shapes.half_w = flat["half_width"][index]
        elif kind == BOX:
            angle = pose[2, index]
            shapes.cos, shapes.sin = np.cos(angle), np.sin(angle)
            shapes.half_w, shapes.half_h = flat["half_width"][index], flat["half_height"][index]
        elif kind == PLANE:
            shapes.normal_x, shapes.normal_y = flat["normal_x"][index], flat["normal_y"][index]
        return shapes

    def _wake_touched(
        self,
        flat: dict[str, np.ndarray],
        point_a: np.ndarray,
        point_b: np.ndarray,
        springs: tuple | None,
    ) -> None:
        """Something awake touching a sleeping body wakes the sleeper's whole island."""
        awake, dynamic = flat["awake"], self._dynamic_flat
        first, second = point_a, point_b
        if springs is not None:
            first, second = (
                np.concatenate([first, springs[0]]),
                np.concatenate([second, springs[1]]),
            )
        if first.size == 0:
            return
        asleep_a, asleep_b = ~awake[first] & dynamic[first], ~awake[second] & dynamic[second]
        hit = np.concatenate([first[asleep_a & awake[second]], second[asleep_b & awake[first]]])
        if hit.size:
            self._wake_islands(np.unique(hit))

    def _body_terms(
        self, flat: dict[str, np.ndarray], h: float
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Which bodies move, their accelerations and drag factors for one substep.

        Gravity acts as the force ``m g`` (an acceleration ``g``); applied forces as
        ``F / m`` and ``torque / I``. Drag multiplies velocity by ``exp(-drag h)`` per
        substep: exactly the exponential decay ``exp(-drag t)``, for any step size.
        """
        awake = flat["awake"] & flat["enabled"]
        movable = awake & self._dynamic_flat  # moved by forces and contacts
        force = flat["force"]
        accel = np.empty_like(force)
        accel[0] = np.where(movable, self._gravity[0] + force[0] * flat["inv_mass"], 0.0)
        accel[1] = np.where(movable, self._gravity[1] + force[1] * flat["inv_mass"], 0.0)
        accel[2] = np.where(movable, force[2] * flat["inv_moment"], 0.0)
        damping = np.empty_like(force)
        damping[0] = np.where(movable, np.exp(-h * flat["linear_drag"]), 1.0)
        damping[1] = damping[0]
        damping[2] = np.where(movable, np.exp(-h * flat["angular_drag"]), 1.0)
        return movable, accel, damping, awake.astype(np.float64)

    def _contacts(
        self,
        flat: dict[str, np.ndarray],
        movable: np.ndarray,
        accel: np.ndarray,
        points: Points,
        keys: np.ndarray,
        body_a: np.ndarray,
        body_b: np.ndarray,
        h: float,
    ) -> Contacts:
        """Constraints for the points: keys, materials, soft parameters, warm start."""
        pair = points.pair
        a, b = body_a[pair], body_b[pair]
        pkey = point_keys(keys[pair], points.feature)
        kind, _, slot_a, slot_b = split_keys(keys[pair], self._batch, self._bodies.capacity)
        local = ((kind * _LOCAL_RADIX + slot_a) * _LOCAL_RADIX + slot_b) * FEATURES + points.feature
        hertz = min(self.contact_hertz, 0.25 / h)
        softness = (
            soft_constraint(hertz, self.contact_damping_ratio, h),
            soft_constraint(2.0 * hertz, self.contact_damping_ratio, h),
        )
        bodies = {
            "inv_mass": flat["inv_mass"],
            "inv_moment": flat["inv_moment"],
            "restitution": flat["restitution"],
            "friction": flat["friction"],
            "movable": movable,
            "vel": flat["vel"],
            "accel": accel,
        }
        return build(
            pkey,
            local,
            a,
            b,
            points.normal_x,
            points.normal_y,
            (points.anchor_ax, points.anchor_ay),
            (points.anchor_bx, points.anchor_by),
            points.separation,
            bodies,
            self._cache,
            self._rules,
            softness,
        )

    def _active_springs(self, flat: dict[str, np.ndarray]) -> tuple | None:
        """Flat body indices and parameters of the springs that act this step, or None."""
        slots = np.flatnonzero(self._spring_a >= 0)
        if slots.size == 0:
            return None
        n, s = self._bodies.capacity, self._springs
        world = np.repeat(np.arange(self._batch), slots.size)
        slot = np.tile(slots, self._batch)
        a, b = world * n + self._spring_a[slot], world * n + self._spring_b[slot]
        on = s["enabled"][world, slot] & flat["enabled"][a] & flat["enabled"][b]
        if not on.any():
            return None
        world, slot, a, b = world[on], slot[on], a[on], b[on]
        params = {
            "anchor_a": s["anchor_a"][:, world, slot],
            "anchor_b": s["anchor_b"][:, world, slot],
            "rest_length": s["rest_length"][world, slot],
            "stiffness": s["stiffness"][world, slot],
            "damping": s["damping"][world, slot],
        }
        return a, b, params

    def _spring_inverse(
        self, flat: dict[str, np.ndarray], movable: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        return (
            np.where(movable, flat["inv_mass"], 0.0),
            np.where(movable, flat["inv_moment"], 0.0),
        )

    def _apply_springs(
        self, flat: dict[str, np.ndarray], movable: np.ndarray, springs: tuple, h: float
    ) -> None:
        inv_mass, inv_moment = self._spring_inverse(flat, movable)
        change = np.zeros_like(flat["vel"])
        spring_forces.add_forces(
            change,
            flat["pose"],
            flat["vel"],
            inv_mass,
            inv_moment,
            springs[0],
            springs[1],
            springs[2],
        )
        flat["vel"] += h * change

    def _finish(
        self,
        flat: dict[str, np.ndarray],
        movable: np.ndarray,
        contacts: Contacts,
        springs: tuple | None,
        dt: float,
    ) -> None:
        """Store impulses for warm starting, clear forces, update sleep, advance time."""
        awake, enabled = flat["awake"], flat["enabled"]
        # Keep the impulses of pairs that slept through this step (they were not solved).
        first, second = self._cached_bodies()
        dormant = ~awake[first] & ~awake[second] & enabled[first] & enabled[second]
        self._cache = Cache.merge(contacts.cache(), self._cache.take(np.flatnonzero(dormant)))
        flat["force"][...] = 0.0
        kinematic = self._kinematic_flat
        if kinematic.any():  # a kinematic body is awake while it moves
            awake[kinematic] = enabled[kinematic] & np.any(flat["vel"][:, kinematic] != 0, axis=0)
        if self.sleeping:
            self._update_sleep(flat, movable, contacts, springs, dt)
        self._time += dt
        self.steps += 1
        self.last_contacts = contacts

    def _update_sleep(
        self,
        flat: dict[str, np.ndarray],
        movable: np.ndarray,
        contacts: Contacts,
        springs: tuple | None,
        dt: float,
    ) -> None:
        vel = flat["vel"]
        speed = np.maximum(np.hypot(vel[0], vel[1]), np.abs(vel[2]) * flat["bound"])
        sleep_time = flat["sleep_time"]
        sleep_time[...] = np.where(movable & (speed < self.sleep_speed), sleep_time + dt, 0.0)
        if not (sleep_time >= self.time_to_sleep).any():
            return
        first, second = contacts.body_a, contacts.body_b
        if springs is not None:
            first, second = (
                np.concatenate([first, springs[0]]),
                np.concatenate([second, springs[1]]),
            )
        joined = movable[first] & movable[second]
        sleepy, label = fall_asleep(
            flat["awake"], movable, sleep_time, self.time_to_sleep, (first[joined], second[joined])
        )
        if sleepy.size:
            flat["awake"][sleepy] = False
            vel[:, sleepy] = 0.0
            flat["island"][sleepy] = label[sleepy]

    # -- readouts and queries -----------------------------------------------------------------
    def energy(self) -> Energy:
        """Kinetic (linear, rotational), gravitational potential and spring energy (J).

        Potential energy is ``-m g . position``, zero at the origin. Fixed and kinematic
        bodies are excluded (they are driven, not part of the system).
        """
        flat = self._flat()
        return energy_of(
            flat, self._dynamic_flat, self._gravity, self._active_springs(flat), self._batch
        )

    def query_point(self, point: Any, world: int = 0) -> list:
        """The circles and boxes that contain a world point (in world ``world`` of the
        batch), in slot order. Planes are left out: they are the scenery."""
        p = _checks.vector2("point", point)
        if not 0 <= world < self._batch:
            raise ValueError(f"world must be in [0, {self._batch}), got {world}")
        b = self._bodies
        pose = b["pose"][:, world]
        dx, dy = p[0] - pose[0], p[1] - pose[1]
        c, s = np.cos(pose[2]), np.sin(pose[2])
        lx, ly = c * dx + s * dy, -s * dx + c * dy
        hw, hh = b["half_width"][world], b["half_height"][world]
        inside = np.where(
            self._kind == CIRCLE,
            lx * lx + ly * ly <= hw * hw,
            (np.abs(lx) <= hw) & (np.abs(ly) <= hh),
        )
        inside &= ((self._kind == CIRCLE) | (self._kind == BOX)) & b["enabled"][world]
        return [self._body_objects[i] for i in np.flatnonzero(inside)]
