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
from ._stages import Integrator, StepStages, StepTerms
from .contacts import MIXING_RULES, Cache, Contacts
from .energy import Energy, energy_of
from .state import BOX, CIRCLE, FIXED


class World(SlotStore, SnapshotMixin, StepStages):
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
      against immovable bodies). ``contact_push_speed`` (m/s) caps how fast each
      contact pushes overlapping bodies apart, so a heavily overlapping start does not
      explode (a body pushed by several contacts at once can move faster).
    * ``speculative_distance`` (m): contacts are made this much before shapes touch, on
      top of how far the pair can close in the step (at most a quarter of a body's size,
      so small bodies get proportionally smaller distances).
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
        self._version = 0  # bumped by every change to who moves or to body parameters
        self._terms: StepTerms | None = None
        self._woken: list[np.ndarray] = []  # bodies whose step terms need a refresh
        self._forces_pending = False
        self._speculative = _checks.non_negative("speculative_distance", speculative_distance)
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
        self.speculative_distance = speculative_distance
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
        self._touch()

    @property
    def speculative_distance(self) -> float:
        """How far apart (m) shapes get a contact before they touch, on top of how far they
        can close in the step; a body uses at most a quarter of its size."""
        return self._speculative

    @speculative_distance.setter
    def speculative_distance(self, value: float) -> None:
        self._speculative = _checks.non_negative("speculative_distance", value)
        self._half_spec = self._speculative_half(np.arange(self._views["bound"].size))

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
        if not self._views["awake"].any():  # everything asleep or fixed: nothing can move
            self._time += dt
            self.steps += 1
            self.last_contacts = None
            return
        h = dt / self._substeps
        terms = self._step_terms(h)
        springs = self._active_springs() if self._springs_used else None
        speed = self._speed_bound(terms)
        keys, body_a, body_b = self._candidate_pairs(terms, speed, dt)
        points = self._narrowphase(keys, body_a, body_b, speed, dt)
        touching = (body_a[points.pair], body_b[points.pair])
        if self._wake_touched(*touching, springs):
            terms = self._step_terms(h)
        accel_h = self._accelerations(terms, h)
        if springs is not None:
            spring_forces.check_stable(
                self._views["pose"], terms.inv_mass, terms.inv_moment, *springs, h
            )
        contacts = None
        if points.pair.size:
            contacts = self._contacts(terms, accel_h, points, keys, body_a, body_b, h)
        self._substeps_loop(terms, accel_h, contacts, springs, h)
        self._finish(terms, contacts, touching, speed, springs, dt)

    def _substeps_loop(
        self,
        terms: StepTerms,
        accel_h: np.ndarray,
        contacts: Contacts | None,
        springs: tuple | None,
        h: float,
    ) -> None:
        """Box2D v3's soft step: per substep integrate velocities, warm start, solve with
        the soft bias, integrate positions, relax without it; then restitution once."""
        vel, pose = self._views["vel"], self._views["pose"]
        push, inv_h = self.contact_push_speed, 1.0 / h
        integrate = Integrator(
            vel, pose, terms, accel_h, self._gravity.any() or self._forces_pending
        )
        if contacts is not None:
            blocks = solver.blocks(contacts)
            separation = contacts.separation
        for _ in range(self._substeps):
            integrate.velocities()  # drag, then gravity and forces
            if springs is not None:
                self._apply_springs(terms, springs, h)
            if contacts is not None:
                solver.warm_start(contacts, vel)
                solver.solve(contacts, blocks, vel, separation, inv_h, True, push)
            integrate.positions()
            if contacts is not None:
                separation = solver.separation(contacts, pose)
                solver.solve(contacts, blocks, vel, separation, inv_h, False, push)
        if contacts is not None:
            solver.restitution(contacts, vel, self.restitution_threshold, h)

    # -- readouts and queries -----------------------------------------------------------------
    def energy(self) -> Energy:
        """Kinetic (linear, rotational), gravitational potential and spring energy (J).

        Potential energy is ``-m g . position``, zero at the origin. Fixed and kinematic
        bodies are excluded (they are driven, not part of the system).
        """
        return energy_of(
            self._views, self._dynamic_flat, self._gravity, self._active_springs(), self._batch
        )

    def at_rest(self) -> Any:
        """True for a world in which nothing moves (every body asleep or fixed): a bool,
        or one per world."""
        b = self._bodies
        rest = ~(b["awake"] & b["enabled"]).any(axis=1)
        return bool(rest[0]) if self._batch == 1 else rest

    def stop(self, worlds: Any = None) -> None:
        """Bring every body of the given worlds (default: all) to rest at once: velocities
        zero, dynamic bodies asleep. A game that caps how long a move may run uses this to
        end it the same way whether a world is stepped alone or in a batch."""
        b = self._bodies
        rows = np.arange(self._batch) if worlds is None else np.asarray(worlds).reshape(-1)
        if rows.dtype.kind not in "iu" or np.any(rows < 0) or np.any(rows >= self._batch):
            raise ValueError(f"worlds must be indices in [0, {self._batch}), got {worlds!r}")
        n = b.capacity
        flat = (rows[:, None] * n + np.flatnonzero(self._motion != FIXED)[None, :]).ravel()
        b.flat("vel")[:, flat] = 0.0
        dynamic = flat[self._dynamic_flat[flat]]
        b.flat("awake")[flat] = False
        b.flat("sleep_time")[dynamic] = 0.0
        b.flat("island")[dynamic] = dynamic  # each its own island: any touch wakes it alone
        self._touch()

    def impulses(self, approach_speed: float = 0.0) -> Any:
        """The contact impulse each body received in the last step (N s): the sum over its
        contact points of the normal impulses, shape ``(slots,)`` or ``(batch, slots)``
        (index by ``body.slot``). Games use it for damage: how hard was it hit.

        ``approach_speed`` (m/s) keeps only the points whose bodies were closing faster
        than that along the normal at the start of the step: impacts, not the steady
        push of a resting stack (whose points close at no more than about ``g dt``)."""
        approach_speed = _checks.non_negative("approach_speed", approach_speed)
        total = np.zeros(self._batch * self._bodies.capacity)
        contacts = self.last_contacts
        if contacts is not None and contacts.size:
            impulse = contacts.step_impulse
            if approach_speed > 0.0:
                impulse = np.where(contacts.relative_velocity < -approach_speed, impulse, 0.0)
            np.add.at(total, contacts.body_a, impulse)
            np.add.at(total, contacts.body_b, impulse)
        total = total.reshape(self._batch, -1)
        return total[0] if self._batch == 1 else total

    def touches(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The contact points that pushed in the last step: ``(world, slot_a, slot_b,
        impulse)`` arrays, one entry per point, with the normal impulse it applied over
        the step (N s). Speculative points that never touched are left out. Games use it
        for rules such as "the cue ball must hit a ball"."""
        contacts = self.last_contacts
        if contacts is None or contacts.size == 0:
            empty = np.zeros(0, np.int64)
            return empty, empty, empty, np.zeros(0)
        pushed = np.flatnonzero(contacts.step_impulse > 0.0)
        n = self._bodies.capacity
        a, b = contacts.body_a[pushed], contacts.body_b[pushed]
        return a // n, a % n, b % n, contacts.step_impulse[pushed]

    def array(self, name: str) -> np.ndarray:
        """A read-only view of one body field in every world, for vectorised readouts:
        ``'pose'`` and ``'vel'`` have shape ``(3, batch, slots)`` (x, y, angle and their
        rates), the others ``(batch, slots)``; ``state.BODY_FIELDS`` lists them with their
        units. Index slots by ``body.slot``. Writes go through the objects, which keep the
        derived state (masses, broadphase, sleep) consistent."""
        if name not in self._bodies.arrays:
            names = ", ".join(self._bodies.arrays)
            raise ValueError(f"name must be one of {names}, got {name!r}")
        view = self._bodies[name].view()
        view.flags.writeable = False
        return view

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
