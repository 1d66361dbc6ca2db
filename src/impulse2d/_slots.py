"""The World's bookkeeping of slots: adding and removing objects, and the reads and
writes behind every property of ``Circle``, ``Box``, ``Plane`` and ``Spring``.

Kept apart from ``world.py`` so that the step pipeline there reads on its own.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from . import _checks
from .broadphase import Broadphase, decode_keys, plane_pairs, rekey
from .contacts import Cache
from .narrowphase import FEATURES
from .shapes import Body, Plane, _Slot, moment_of
from .springs import Spring
from .state import (
    BODY_FIELDS,
    BOX,
    CIRCLE,
    DYNAMIC,
    FIXED,
    FREE,
    KINEMATIC,
    PLANE,
    SPRING_FIELDS,
    Table,
    grown,
)


class SlotStore:
    """Mixin of ``World``: body and spring slots and the object facades bound to them."""

    _batch: int
    _cache: Cache

    def _init_slots(self, batch: int) -> None:
        self._batch = batch
        self._bodies = Table(BODY_FIELDS, batch, 8)
        self._kind = np.full(8, FREE, np.int8)
        self._motion = np.zeros(8, np.int8)
        self._body_objects: list[_Slot | None] = [None] * 8
        self._springs = Table(SPRING_FIELDS, batch, 4)
        self._spring_a = np.full(4, -1, np.int64)
        self._spring_b = np.full(4, -1, np.int64)
        self._spring_objects: list[Spring | None] = [None] * 4
        self._broadphase = Broadphase(batch, 8)
        self._structure_changed()

    # -- public ------------------------------------------------------------------------------
    @property
    def batch_size(self) -> int:
        """Number of worlds stepped together (1 for a plain world)."""
        return self._batch

    @property
    def bodies(self) -> list[_Slot]:
        """Every Circle, Box and Plane in the world, in slot order."""
        return [obj for obj in self._body_objects if obj is not None]

    @property
    def springs(self) -> list[Spring]:
        """Every Spring in the world, in slot order."""
        return [obj for obj in self._spring_objects if obj is not None]

    def add(self, obj: Any) -> Any:
        """Add a Circle, Box, Plane or Spring to every world of the batch; returns ``obj``."""
        if isinstance(obj, Spring):
            return self._add_spring(obj)
        if not isinstance(obj, (Body, Plane)):
            raise TypeError(f"add takes a Circle, Box, Plane or Spring, got {type(obj).__name__}")
        if obj._world is not None:
            raise ValueError(f"{obj!r} is already in a world; remove it first")
        free = np.flatnonzero(self._kind == FREE)
        if free.size == 0:
            self._grow_bodies(grown(self._bodies.capacity, self._bodies.capacity + 1))
            free = np.flatnonzero(self._kind == FREE)
        slot = int(free[0])
        cls = type(obj)
        staged = {}
        for name, value in obj._values.items():  # validate every value before writing any
            field = getattr(cls, name)
            staged[name] = (field, _checks.batched(name, value, self._batch, field.tail))
        for field, array in staged.values():
            self._store(slot, field.array, field.rows, array * field.scale)
        b = self._bodies
        self._kind[slot] = obj._kind
        self._motion[slot] = obj._motion
        if obj._kind == CIRCLE:
            b["half_height"][:, slot] = b["half_width"][:, slot]
        if obj._kind == PLANE:
            b["normal_x"][:, slot], b["normal_y"][:, slot] = obj._normal
        b["enabled"][:, slot] = True
        b["awake"][:, slot] = obj._motion != FIXED
        b["sleep_time"][:, slot] = 0.0
        b["island"][:, slot] = -1
        b["force"][:, :, slot] = 0.0
        self._body_objects[slot] = obj
        obj._world, obj._slot, obj._values = self, slot, {}
        self._structure_changed(slot)
        self._rebuild_mass(slot)
        self._forget_slot(slot)
        return obj

    def remove(self, obj: Any) -> None:
        """Take an object out of every world. It keeps its values and can be added again."""
        if getattr(obj, "_world", None) is not self:
            raise ValueError(f"{obj!r} is not in this world")
        if isinstance(obj, Spring):
            values = {
                name: getattr(obj, name)
                for name in ("rest_length", "stiffness", "damping", "anchor1", "anchor2")
            }
            self._springs["enabled"][:, obj._slot] = False
            self._spring_a[obj._slot] = self._spring_b[obj._slot] = -1
            self._spring_objects[obj._slot] = None
            self._springs_used = bool((self._spring_a >= 0).any())
            self._wake_slot(self.body_slot(obj.body1))
            obj._world, obj._slot, obj._values = None, -1, values
            return
        attached = [s for s in self.springs if obj in (s.body1, s.body2)]
        if attached:
            raise ValueError(f"{obj!r} is attached to {len(attached)} spring(s); remove them first")
        values = {name: getattr(obj, name) for name in obj._saved}
        slot = obj._slot
        self._wake_neighbours(self._slot_flat(slot))
        self._kind[slot] = FREE
        self._bodies["enabled"][:, slot] = False
        self._bodies["awake"][:, slot] = False
        self._body_objects[slot] = None
        self._forget_slot(slot)
        obj._world, obj._slot, obj._values = None, -1, values
        self._structure_changed(slot)

    def body_slot(self, body: _Slot) -> int:
        if body._world is not self:
            raise ValueError(f"{body!r} is not in this world")
        return body._slot

    # -- structure -----------------------------------------------------------------------------
    def _structure_changed(self, slot: int | None = None) -> None:
        """Recompute everything derived from the slots' kinds and motion types, after a
        change to one slot (``slot``) or to the layout (grown, replicated, new)."""
        kind, motion = self._kind, self._motion
        solid = (kind == CIRCLE) | (kind == BOX)
        plane = kind == PLANE
        dynamic = (motion == DYNAMIC) & solid
        # Two slots may collide if at least one is dynamic, neither is free, and they are
        # not both planes; a slot never collides with itself. The matrix is slots x slots,
        # so one add updates its row and column only: building n bodies stays O(n^2).
        used = solid | plane
        if getattr(self, "_allowed", None) is None or self._allowed.shape[0] != kind.size:
            slot = None  # a new or grown layout: the whole matrix
        rows = np.arange(kind.size) if slot is None else np.array([slot])
        block = (used[rows, None] & used[None, :]) & (dynamic[rows, None] | dynamic[None, :])
        block &= ~(plane[rows, None] & plane[None, :])
        block[np.arange(rows.size), rows] = False
        if slot is None:
            self._allowed = block
        else:
            self._allowed[slot, :] = block[0]
            self._allowed[:, slot] = block[0]
        allowed = self._allowed
        self._plane_keys = plane_pairs(kind, allowed, self._batch)
        self._plane_a, self._plane_b = decode_keys(self._plane_keys, self._batch, kind.size)
        batch = self._batch
        self._dynamic_flat = np.tile(dynamic, batch)
        self._solid_flat = np.tile(solid, batch)
        self._kinematic_flat = np.flatnonzero(np.tile((motion == KINEMATIC) & solid, batch))
        self._box_flat = np.flatnonzero(np.tile(kind == BOX, batch))
        self._views = {field.name: self._bodies.flat(field.name) for field in BODY_FIELDS}
        bound = self._views["bound"]
        # Broadphase extents: a circle's is its radius; a box's is refreshed from its angle
        # whenever it moves or is re-inserted (see _stages._update_extents).
        self._extent_x, self._extent_y = bound.copy(), bound.copy()
        self._margin_base = self._fat_margin(np.arange(bound.size))
        self._half_spec = self._speculative_half(np.arange(bound.size))
        self._springs_used = bool((self._spring_a >= 0).any())
        self._touch()

    def _fat_margin(self, flat: np.ndarray) -> np.ndarray:
        """How much larger than its tight box a body's fat box is, before travel is added:
        half its smaller half size if it can move, nothing if it is fixed (a long fixed
        cushion with a margin proportional to its length would pair with every ball)."""
        views = self._views
        smaller = np.minimum(views["half_width"][flat], views["half_height"][flat])
        movable = np.tile(self._motion != FIXED, self._batch)[flat]
        return np.where(movable, 0.5 * smaller, 0.0)

    def _speculative_half(self, flat: np.ndarray) -> np.ndarray:
        """Half of each body's speculative distance: the world's, but at most a quarter of
        the body's size, so small bodies (pool balls) are not given contacts whole radii
        away (Box2D scales its speculative distance with its length unit instead).
        Planes have no size and take the world's."""
        bound = self._views["bound"][flat]
        plane = np.tile(self._kind == PLANE, self._batch)[flat]
        size = np.where(plane, np.inf, 0.25 * bound)
        return 0.5 * np.minimum(self._speculative, size)

    def _touch(self, flat: np.ndarray | None = None) -> None:
        """Something changed who moves or a body parameter: rebuild the step terms, all of
        them, or (``flat`` given) only those of the bodies that woke up or fell asleep."""
        if flat is None:
            self._version += 1
            self._woken = []
        else:
            self._woken.append(flat)

    def _grow_bodies(self, capacity: int) -> None:
        old = self._bodies.capacity
        self._bodies.grow(capacity)
        self._kind = np.concatenate([self._kind, np.full(capacity - old, FREE, np.int8)])
        self._motion = np.concatenate([self._motion, np.zeros(capacity - old, np.int8)])
        self._body_objects += [None] * (capacity - old)
        self._broadphase = Broadphase(self._batch, capacity)
        cache = self._cache
        cache.keys = rekey(cache.keys, self._batch, old, self._batch, capacity)
        cache.body_a, cache.body_b = decode_keys(cache.keys // FEATURES, self._batch, capacity)

    def _cached_bodies(self) -> tuple[np.ndarray, np.ndarray]:
        """Flat indices of the two bodies of every point in the warm-start cache."""
        return self._cache.body_a, self._cache.body_b

    def _slot_flat(self, slot: int) -> np.ndarray:
        """Flat indices of a slot in every world."""
        return np.arange(self._batch) * self._bodies.capacity + slot

    def _forget_slot(self, slot: int) -> None:
        """Drop cached impulses of a slot and make the broadphase look at it again."""
        self._broadphase.mark(self._slot_flat(slot))
        if self._cache.keys.size:
            first, second = self._cached_bodies()
            n = self._bodies.capacity
            keep = (first % n != slot) & (second % n != slot)
            self._cache = self._cache.take(np.flatnonzero(keep))

    # -- reads and writes behind the facades -------------------------------------------------
    def _read_slot(self, slot: int, array: str, rows: Any) -> Any:
        data = self._bodies[array]
        if rows is None:
            values = data[:, slot].copy()
        elif isinstance(rows, slice):
            values = data[rows, :, slot].T.copy()
        else:
            values = data[rows, :, slot].copy()
        if self._batch == 1:
            values = values[0]
            return values.item() if values.ndim == 0 else values
        return values

    def _store(self, slot: int, array: str, rows: Any, values: np.ndarray) -> None:
        data = self._bodies[array]
        if rows is None:
            data[:, slot] = values
        elif isinstance(rows, slice):
            data[rows, :, slot] = values.T
        else:
            data[rows, :, slot] = values

    def _write_slot(
        self, slot: int, array: str, rows: Any, values: np.ndarray, moves: bool
    ) -> None:
        if array == "vel" and self._motion[slot] == FIXED and np.any(values != 0.0):
            name = "velocity" if isinstance(rows, slice) else "angular_velocity"
            raise ValueError(f"{name} of a fixed body must be 0; use kinematic=True")
        # Only the worlds whose value changes are touched: a game that rewrites one world
        # of a batch (a respotted cue ball) must not wake the same body in the others,
        # or stepping the batch would stop giving what each world gives alone.
        before = self._read_slot(slot, array, rows)
        changed = np.asarray(before != values.reshape(np.shape(before)))
        changed = changed.reshape(self._batch, -1).any(axis=1)
        self._store(slot, array, rows, values)
        flat = self._slot_flat(slot)[changed]
        if moves:
            self._forget_moves(flat)
        self._wake_islands(flat)
        self._touch()

    def _forget_moves(self, flat: np.ndarray) -> None:
        """Teleported or resized bodies: re-query them and wake what was resting on them."""
        self._broadphase.mark(flat)
        self._wake_neighbours(flat)

    def _rebuild_mass(self, slot: int) -> None:
        """Moment of inertia, inverse mass and bounding radius from mass and size."""
        b = self._bodies
        kind = int(self._kind[slot])
        if kind == CIRCLE:
            b["half_height"][:, slot] = b["half_width"][:, slot]
        mass, hw, hh = b["mass"][:, slot], b["half_width"][:, slot], b["half_height"][:, slot]
        moment = moment_of(kind, mass, hw, hh)
        dynamic = self._motion[slot] == DYNAMIC and kind != PLANE
        b["moment"][:, slot] = moment
        b["inv_mass"][:, slot] = 1.0 / mass if dynamic else 0.0
        b["inv_moment"][:, slot] = 1.0 / moment if dynamic else 0.0
        b["bound"][:, slot] = hw if kind == CIRCLE else np.hypot(hw, hh) if kind == BOX else 0.0
        self._refresh_sizes(self._slot_flat(slot))
        self._touch()

    def _refresh_sizes(self, flat: np.ndarray) -> None:
        """Recompute what the broadphase derives from body sizes (extents, fat margins,
        speculative distances) and make it look at those bodies again."""
        self._extent_x[flat] = self._extent_y[flat] = self._views["bound"][flat]
        self._margin_base[flat] = self._fat_margin(flat)
        self._half_spec[flat] = self._speculative_half(flat)
        self._broadphase.mark(flat)

    def _set_enabled(self, slot: int, value: Any) -> None:
        flags = np.asarray(value)
        if flags.dtype != np.bool_ or flags.shape not in ((), (self._batch,)):
            raise ValueError(f"enabled must be a bool or {self._batch} bools, got {value!r}")
        flags = np.broadcast_to(flags, (self._batch,))
        b = self._bodies
        changed = np.flatnonzero(b["enabled"][:, slot] != flags)
        if changed.size == 0:
            return
        flat = changed * b.capacity + slot
        self._wake_neighbours(flat[~flags[changed]])
        b["enabled"][changed, slot] = flags[changed]
        b["awake"][changed, slot] = flags[changed] & (self._motion[slot] != FIXED)
        b["sleep_time"][changed, slot] = 0.0
        self._broadphase.mark(flat)
        # Only these bodies' step terms change (who moves, who is in the broadphase): a
        # game that pots a ball in one of a thousand worlds should not rebuild them all.
        self._touch(flat)

    # -- waking -------------------------------------------------------------------------------
    def _wake_slot(self, slot: int) -> None:
        self._wake_islands(self._slot_flat(slot))

    def _wake_islands(self, flat: np.ndarray) -> None:
        """Wake the sleeping dynamic bodies among ``flat`` together with their islands."""
        b = self._bodies
        awake, island = b.flat("awake"), b.flat("island")
        enabled = b.flat("enabled")
        sleepers = flat[~awake[flat] & self._dynamic_flat[flat] & enabled[flat]]
        if sleepers.size == 0:
            return
        ids = island[sleepers]
        members = np.flatnonzero(np.isin(island, ids[ids >= 0]) & ~awake)
        members = np.union1d(members, sleepers)
        awake[members] = True
        b.flat("sleep_time")[members] = 0.0
        island[members] = -1
        self._touch(members)

    def _wake_neighbours(self, flat: np.ndarray) -> None:
        """Wake everything that was in contact with the given bodies at the last step."""
        if self._cache.keys.size == 0 or flat.size == 0:
            return
        first, second = self._cached_bodies()
        hit = np.isin(first, flat)
        other = np.concatenate([second[hit], first[np.isin(second, flat)]])
        self._wake_islands(np.unique(other))

    # -- applying forces ---------------------------------------------------------------------
    def _apply(self, slot: int, mode: str, vector: Any, point: Any, name: str) -> None:
        b = self._bodies
        push = _checks.batched(name, vector, self._batch, (2,))
        centre = b["pose"][:2, :, slot].T
        where = centre if point is None else _checks.batched("point", point, self._batch, (2,))
        r = where - centre
        torque = r[:, 0] * push[:, 1] - r[:, 1] * push[:, 0]
        if mode == "force":
            b["force"][:2, :, slot] += push.T
            b["force"][2, :, slot] += torque
            self._forces_pending = True
        else:
            b["vel"][:2, :, slot] += push.T * b["inv_mass"][:, slot]
            b["vel"][2, :, slot] += torque * b["inv_moment"][:, slot]
        # Wake the body only in the worlds it is pushed in (a batch of shots where some
        # worlds sit out must leave those exactly as they are).
        self._wake_islands(self._slot_flat(slot)[np.any(push != 0.0, axis=1)])

    # -- springs ------------------------------------------------------------------------------
    def _add_spring(self, spring: Spring) -> Spring:
        if spring._world is not None:
            raise ValueError(f"{spring!r} is already in a world; remove it first")
        for name, body in (("body1", spring.body1), ("body2", spring.body2)):
            if body._world is not self:
                raise ValueError(f"{name} of the spring must be in this world; add it first")
        slot_a, slot_b = spring.body1._slot, spring.body2._slot
        values = spring._values
        anchors = {
            k: _checks.batched(k, values[k], self._batch, (2,)) for k in ("anchor1", "anchor2")
        }
        scalars = {
            k: _checks.batched(k, values[k], self._batch, ()) for k in ("stiffness", "damping")
        }
        free = np.flatnonzero(self._spring_a < 0)
        if free.size == 0:
            capacity = self._springs.capacity
            self._springs.grow(2 * capacity)
            self._spring_a = np.concatenate([self._spring_a, np.full(capacity, -1, np.int64)])
            self._spring_b = np.concatenate([self._spring_b, np.full(capacity, -1, np.int64)])
            self._spring_objects += [None] * capacity
            free = np.flatnonzero(self._spring_a < 0)
        slot = int(free[0])
        s = self._springs
        s["anchor_a"][:, :, slot] = anchors["anchor1"].T
        s["anchor_b"][:, :, slot] = anchors["anchor2"].T
        s["stiffness"][:, slot] = scalars["stiffness"]
        s["damping"][:, slot] = scalars["damping"]
        self._spring_a[slot], self._spring_b[slot] = slot_a, slot_b
        s["enabled"][:, slot] = True
        self._spring_objects[slot] = spring
        spring._world, spring._slot = self, slot
        if values["rest_length"] is None:
            s["rest_length"][:, slot] = np.atleast_1d(spring.length)
        else:
            s["rest_length"][:, slot] = _checks.batched(
                "rest_length", values["rest_length"], self._batch, ()
            )
        spring._values = {}
        self._springs_used = True
        self._wake_slot(slot_a)
        self._wake_slot(slot_b)
        return spring

    def _read_spring(self, slot: int, name: str) -> Any:
        array = {"anchor1": "anchor_a", "anchor2": "anchor_b"}.get(name, name)
        data = self._springs[array]
        values = data[:, :, slot].T.copy() if data.ndim == 3 else data[:, slot].copy()
        if self._batch == 1:
            values = values[0]
            return values.item() if values.ndim == 0 else values
        return values

    def _write_spring(self, slot: int, name: str, values: np.ndarray) -> None:
        array = {"anchor1": "anchor_a", "anchor2": "anchor_b"}.get(name, name)
        data = self._springs[array]
        if data.ndim == 3:
            data[:, :, slot] = values.T
        else:
            data[:, slot] = values
        self._wake_slot(self._spring_a[slot])
        self._wake_slot(self._spring_b[slot])
