"""Snapshots (exact save and restore of the whole state) and replication of a world.

A snapshot holds copies of every body and spring array, the warm-start impulses and
the clock, so restoring it and stepping again gives bitwise the same result as the
first time. The broadphase pairs are not saved: they are a cache whose content does
not change any result (every pair that can touch is always in it), so a restore just
asks the broadphase to look at the restored worlds again.

``restore(snapshot, worlds=...)`` writes into some worlds of a batch only, from a
snapshot of one world (copied into each) or of as many worlds as are named. That is how
a vector environment resets the worlds whose episode ended.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass
from typing import Any

import numpy as np

from .broadphase import Broadphase, decode_keys, rekey, split_keys
from .contacts import Cache
from .narrowphase import FEATURES


@dataclass(frozen=True)
class Snapshot:
    """The complete state of a World (or batch) at one moment. Opaque; see World.snapshot."""

    batch_size: int
    capacity: int
    kind: np.ndarray
    motion: np.ndarray
    spring_a: np.ndarray
    spring_b: np.ndarray
    bodies: dict[str, np.ndarray]
    springs: dict[str, np.ndarray]
    cache: Cache
    time: np.ndarray
    steps: int


class SnapshotMixin:
    """Mixin of ``World``: snapshot, restore, replicate."""

    def snapshot(self) -> Snapshot:
        """A copy of the full state; ``restore`` brings it back exactly."""
        c = self._cache
        return Snapshot(
            batch_size=self._batch,
            capacity=self._bodies.capacity,
            kind=self._kind.copy(),
            motion=self._motion.copy(),
            spring_a=self._spring_a.copy(),
            spring_b=self._spring_b.copy(),
            bodies=self._bodies.copy_arrays(),
            springs=self._springs.copy_arrays(),
            cache=c.copy(),
            time=self._time.copy(),
            steps=self.steps,
        )

    def restore(self, snapshot: Snapshot, worlds: Any = None) -> None:
        """Bring back a snapshot: into every world, or only into ``worlds`` (indices).

        The snapshot must come from a world with the same objects in the same slots (this
        one, a copy from ``replicate``, or one built by the same code). A snapshot of one
        world can be restored into any number of worlds; a snapshot of a batch of the same
        size restores world ``i`` from its world ``i``; otherwise it must have one world per
        named world, taken in order.
        """
        if not isinstance(snapshot, Snapshot):
            raise ValueError(f"snapshot must be a Snapshot, got {type(snapshot).__name__}")
        same = (
            snapshot.capacity == self._bodies.capacity
            and np.array_equal(snapshot.kind, self._kind)
            and np.array_equal(snapshot.motion, self._motion)
            and np.array_equal(snapshot.spring_a, self._spring_a)
            and np.array_equal(snapshot.spring_b, self._spring_b)
        )
        if not same:
            raise ValueError(
                "snapshot does not match this world's objects: it was taken before "
                "objects were added or removed, or from a different scene"
            )
        targets = np.arange(self._batch) if worlds is None else np.asarray(worlds).reshape(-1)
        if targets.dtype.kind not in "iu" or np.any(targets < 0) or np.any(targets >= self._batch):
            raise ValueError(f"worlds must be indices in [0, {self._batch}), got {worlds!r}")
        if snapshot.batch_size == 1:
            sources = np.zeros(targets.size, np.int64)
        elif snapshot.batch_size == self._batch:
            sources = targets
        elif snapshot.batch_size == targets.size:
            sources = np.arange(targets.size)
        else:
            raise ValueError(
                f"snapshot has {snapshot.batch_size} worlds; it can fill any worlds of a batch "
                f"of {snapshot.batch_size}, or exactly {snapshot.batch_size} named worlds, not "
                f"{targets.size} of {self._batch}"
            )
        for table, saved in ((self._bodies, snapshot.bodies), (self._springs, snapshot.springs)):
            for name, array in table.arrays.items():
                array[..., targets, :] = saved[name][..., sources, :]
        # A sleeping body's island id is the flat index of a member: in a different world
        # it must name the same slot of the target world, or waking one world's island
        # would wake the same slots in another.
        _rekey_islands(self._bodies["island"], targets, self._bodies.capacity)
        self._restore_cache(snapshot, targets, sources)
        self._time[targets] = snapshot.time[sources]
        if worlds is None:
            self.steps = snapshot.steps
        n = self._bodies.capacity
        # Sizes may differ per world (a game's levels): refresh what depends on them.
        self._refresh_sizes((targets[:, None] * n + np.arange(n)).ravel())
        self._forces_pending = bool(self._bodies["force"].any())
        self._touch()

    def _restore_cache(self, snapshot: Snapshot, targets: np.ndarray, sources: np.ndarray) -> None:
        n, batch = self._bodies.capacity, self._batch
        keep = ~np.isin(self._world_of(self._cache.keys, batch), targets)
        current = self._cache.take(np.flatnonzero(keep))
        saved = snapshot.cache
        saved_world = self._world_of(saved.keys, snapshot.batch_size)
        parts = [current]
        for source in np.unique(sources):
            rows = np.flatnonzero(saved_world == source)
            for target in targets[sources == source]:
                mapping = np.full(snapshot.batch_size, target)
                part = saved.take(rows)
                part.keys = rekey(part.keys, snapshot.batch_size, n, batch, n, mapping)
                part.body_a, part.body_b = decode_keys(part.keys // FEATURES, batch, n)
                parts.append(part)
        merged = parts[0]
        for part in parts[1:]:
            merged = Cache.merge(merged, part)
        self._cache = merged

    def _world_of(self, keys: np.ndarray, batch: int) -> np.ndarray:
        return split_keys(keys // FEATURES, batch, self._bodies.capacity)[1]

    def replicate(self, batch_size: int) -> Any:
        """A new batch of ``batch_size`` copies of this (single) world, state included.

        Its objects are new facades, in the same slots: ``new.bodies[i]`` is the copy of
        ``self.bodies[i]``; springs likewise.
        """
        from . import _checks

        batch = _checks.positive_int("batch_size", batch_size)
        if self._batch != 1:
            raise ValueError(f"replicate needs a single world, this one has {self._batch}")
        clone = copy.copy(self)
        clone._batch = batch
        snapshot = self.snapshot()
        clone._bodies = copy.copy(self._bodies)
        clone._springs = copy.copy(self._springs)
        for table, saved in ((clone._bodies, snapshot.bodies), (clone._springs, snapshot.springs)):
            table.batch_size = batch
            table.arrays = {
                name: np.repeat(array, batch, axis=-2).copy() for name, array in saved.items()
            }
        _rekey_islands(clone._bodies["island"], np.arange(batch), self._bodies.capacity)
        clone._kind, clone._motion = self._kind.copy(), self._motion.copy()
        clone._spring_a, clone._spring_b = self._spring_a.copy(), self._spring_b.copy()
        clone._time = np.repeat(self._time, batch)
        clone._gravity = self._gravity.copy()
        clone._broadphase = Broadphase(batch, self._bodies.capacity)
        clone._cache = Cache.empty()
        clone._terms = None
        clone.last_contacts = None
        clone._structure_changed()
        clone._restore_cache(snapshot, np.arange(batch), np.zeros(batch, np.int64))
        mapping = {}
        clone._body_objects = []
        for obj in self._body_objects:
            twin = None
            if obj is not None:
                twin = copy.copy(obj)
                twin._world = clone
                mapping[id(obj)] = twin
            clone._body_objects.append(twin)
        clone._spring_objects = []
        for spring in self._spring_objects:
            twin = None
            if spring is not None:
                twin = copy.copy(spring)
                twin._world = clone
                twin.body1, twin.body2 = mapping[id(spring.body1)], mapping[id(spring.body2)]
            clone._spring_objects.append(twin)
        return clone


def _rekey_islands(island: np.ndarray, worlds: np.ndarray, capacity: int) -> None:
    """Make the island ids of sleeping bodies copied into ``worlds`` name their own world.

    An id is the flat index of a member (``world * capacity + slot``). Copied from another
    world it would still name that world, and waking one world's island would wake the
    same slots in every copy."""
    rows = island[worlds]
    asleep = rows >= 0
    rows[asleep] = (worlds[:, None] * capacity + rows % capacity)[asleep]
    island[worlds] = rows
