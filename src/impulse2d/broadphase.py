"""Broadphase: the candidate pairs, kept from step to step and updated only where bodies move.

Each body gets a *tight* bounding box: its axis-aligned bounding box, grown on every
side by how far it can travel this step (``(|vx| + |vy| + |w| R) dt``) and by half the
speculative distance, so two tight boxes overlap whenever the narrowphase could make a
contact. The broadphase stores a *fat* box around each tight one (a margin larger). The
candidate pairs are the pairs of overlapping fat boxes; as long as every tight box
stays inside its fat box the pair list stays valid, so a step in which nothing has
moved far costs a few elementwise operations and nothing per pair. A body that leaves
its fat box is re-fattened and only its pairs are recomputed.

Finding the new pairs of the moved bodies picks by size: a dense test against every
slot of the world while that is cheap (``moved x slots`` up to a few hundred thousand),
otherwise a sweep over the fat squares sorted by their left edge (sort and sweep),
which costs ``O(n log n + candidates)`` instead of ``O(n^2)``. Bodies much larger than
the rest (a long ground box) would make every sweep window huge, so they are
tested densely on their own.

Pairs are identified by an int64 *key*, sorted: ``((kind * B + world) * N + a) * N + b``
with the pair kind (see ``narrowphase``) as the major part. Sorted keys give every
later stage a deterministic order, independent of how many worlds share the batch.

Planes are infinite, so they are not in the squares: every body is paired with every
plane of its world (there are few planes) by ``plane_pairs``.
"""

from __future__ import annotations

import numpy as np

from .narrowphase import BOX_BOX, CIRCLE_BOX, CIRCLE_CIRCLE, FEATURES, PAIR_KIND

# The pair kinds the broadphase holds (planes are paired separately), in key order.
_BROAD_KINDS = np.array(sorted([CIRCLE_CIRCLE, CIRCLE_BOX, BOX_BOX]), dtype=np.int64)
_DENSE_LIMIT = 4_000_000  # moved bodies x slots tested densely before switching to the sweep


def pair_keys(
    kind_pair: np.ndarray, world: np.ndarray, a: np.ndarray, b: np.ndarray, batch: int, slots: int
) -> np.ndarray:
    """Keys of pairs from their kind, world and the slots of A and B."""
    return ((kind_pair * batch + world) * slots + a) * slots + b


def split_keys(keys: np.ndarray, batch: int, slots: int) -> tuple[np.ndarray, ...]:
    """Pair kind, world, slot of A and slot of B of pair keys."""
    slot_b = keys % slots
    rest = keys // slots
    slot_a = rest % slots
    rest = rest // slots
    return rest // batch, rest % batch, slot_a, slot_b


def decode_keys(keys: np.ndarray, batch: int, slots: int) -> tuple[np.ndarray, np.ndarray]:
    """Flat body indices (A, B) of pair keys."""
    _, world, slot_a, slot_b = split_keys(keys, batch, slots)
    return world * slots + slot_a, world * slots + slot_b


def rekey(
    point_keys: np.ndarray,
    batch: int,
    slots: int,
    new_batch: int,
    new_slots: int,
    worlds: np.ndarray | None = None,
) -> np.ndarray:
    """Point keys re-expressed for another batch size or capacity; ``worlds`` maps each old
    world index to a new one (default: the same)."""
    feature = point_keys % FEATURES
    kind, world, slot_a, slot_b = split_keys(point_keys // FEATURES, batch, slots)
    if worlds is not None:
        world = worlds[world]
    return pair_keys(kind, world, slot_a, slot_b, new_batch, new_slots) * FEATURES + feature


class Broadphase:
    """Persistent candidate pairs over fattened bounding squares (see the module docstring).

    ``update`` returns sorted pair keys and the flat body indices of A and B.
    """

    def __init__(self, batch: int, slots: int, dense_limit: int = _DENSE_LIMIT) -> None:
        self.batch, self.slots = batch, slots
        self.dense_limit = dense_limit
        total = batch * slots
        # Fat boxes: centre and half extents. A body with no box has half extents -inf, so
        # it overlaps nothing.
        self.fat_x = np.zeros(total)
        self.fat_y = np.zeros(total)
        self.fat_hx = np.full(total, -np.inf)
        self.fat_hy = np.full(total, -np.inf)
        self.stale = np.ones(total, dtype=bool)  # must be (re)inserted at the next update
        self.any_stale = True
        self.keys = np.zeros(0, np.int64)
        self.body_a = np.zeros(0, np.int64)
        self.body_b = np.zeros(0, np.int64)
        self.updates = 0  # how many bodies were re-queried, for profiling

    def mark(self, flat: np.ndarray | slice) -> None:
        """Bodies that were teleported, resized, enabled or disabled: re-query them."""
        self.stale[flat] = True
        self.any_stale = True

    def update(
        self,
        x: np.ndarray,
        y: np.ndarray,
        extent_x: np.ndarray,
        extent_y: np.ndarray,
        grow: np.ndarray,
        margin: np.ndarray,
        candidates: np.ndarray,
        present: np.ndarray,
        allowed: np.ndarray,
        kind: np.ndarray,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Refresh the pairs and return ``(keys, body_a, body_b)``.

        ``x, y`` are centres and ``extent_x, extent_y`` the half extents of the shapes of
        all ``T`` bodies. A tight box is the shape's box grown by ``grow`` on every side;
        a re-fattened box gets ``margin`` more. ``candidates`` are the bodies that can
        move this step; ``present`` marks enabled non-plane bodies. ``allowed[a, b]``
        says slots a and b may collide, and ``kind`` gives each slot's shape kind.
        """
        c = candidates
        if 2 * c.size > x.size:  # most bodies move: whole arrays beat gathering them
            escaped = (np.abs(x - self.fat_x) + extent_x + grow > self.fat_hx) | (
                np.abs(y - self.fat_y) + extent_y + grow > self.fat_hy
            )
            moved = c[escaped[c]]
        else:
            escaped = (np.abs(x[c] - self.fat_x[c]) + extent_x[c] + grow[c] > self.fat_hx[c]) | (
                np.abs(y[c] - self.fat_y[c]) + extent_y[c] + grow[c] > self.fat_hy[c]
            )
            moved = c[escaped]
        if self.any_stale:
            moved = np.union1d(moved, np.flatnonzero(self.stale))
            self.stale[:] = False
            self.any_stale = False
        if moved.size == 0:
            return self.keys, self.body_a, self.body_b
        self.updates += moved.size
        # The pairs to drop (those of moved bodies) lie in the moved bodies' worlds: look
        # only there, and copy the arrays once, without them.
        moved_mask = np.zeros(x.size, dtype=bool)
        moved_mask[moved] = True
        rows = self.rows_of_worlds(np.unique(moved // self.slots))
        drop = rows[moved_mask[self.body_a[rows]] | moved_mask[self.body_b[rows]]]
        live = present[moved]
        extra = grow[moved] + margin[moved]
        self.fat_x[moved] = x[moved]
        self.fat_y[moved] = y[moved]
        self.fat_hx[moved] = np.where(live, extent_x[moved] + extra, -np.inf)
        self.fat_hy[moved] = np.where(live, extent_y[moved] + extra, -np.inf)

        new_keys, new_a, new_b = self._query(moved[live], moved_mask, present, allowed, kind)
        kept = (self.keys, self.body_a, self.body_b)
        if drop.size:
            kept = tuple(np.delete(array, drop) for array in kept)
        if new_keys.size == 0:
            self.keys, self.body_a, self.body_b = kept
            return kept
        order = np.argsort(new_keys)
        new = (new_keys[order], new_a[order], new_b[order])
        # Merge two sorted lists: where each new key lands among the kept ones.
        total = kept[0].size + new[0].size
        landing = np.searchsorted(kept[0], new[0]) + np.arange(new[0].size)
        is_new = np.zeros(total, dtype=bool)
        is_new[landing] = True
        merged = []
        for old_part, new_part in zip(kept, new, strict=True):
            out = np.empty(total, dtype=old_part.dtype)
            out[landing] = new_part
            out[~is_new] = old_part
            merged.append(out)
        self.keys, self.body_a, self.body_b = merged
        return self.keys, self.body_a, self.body_b

    def rows_of_worlds(self, worlds: np.ndarray) -> np.ndarray:
        """Rows (indices into ``keys``, ascending) of the pairs of ``worlds`` (sorted,
        unique). Keys sort by (kind, world) first, so one world's pairs of one kind are a
        contiguous run, found by two binary searches: the cost follows the worlds asked
        for, not the whole batch."""
        span = self.slots * self.slots
        start = (_BROAD_KINDS[:, None] * self.batch + worlds[None, :]).ravel() * span
        low = np.searchsorted(self.keys, start)
        count = np.searchsorted(self.keys, start + span) - low
        total = int(count.sum())
        if total == 0:
            return np.zeros(0, np.int64)
        # Concatenated ranges [low, low + count): a running index shifted per range.
        shift = np.repeat(low - (np.cumsum(count) - count), count)
        return np.arange(total) + shift

    def _query(
        self,
        moved: np.ndarray,
        moved_mask: np.ndarray,
        present: np.ndarray,
        allowed: np.ndarray,
        kind: np.ndarray,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Keys and flat bodies (A, B) of all valid overlapping pairs with a moved body."""
        if moved.size == 0:
            empty = np.zeros(0, np.int64)
            return empty, empty, empty
        if moved.size * self.slots <= self.dense_limit:
            first, second = self._dense(moved)
        else:
            first, second = self._sweep(moved, present)
        n = self.slots
        slot_1, slot_2 = first % n, second % n
        # Each pair once: when both moved, only the query of the lower slot reports it.
        valid = (
            allowed[slot_1, slot_2] & present[second] & (~moved_mask[second] | (slot_1 < slot_2))
        )
        first, second = first[valid], second[valid]
        slot_1, slot_2 = slot_1[valid], slot_2[valid]
        # Order A, B by (kind, slot) so that kind(A) <= kind(B).
        k1, k2 = kind[slot_1], kind[slot_2]
        swap = (k1 > k2) | ((k1 == k2) & (slot_1 > slot_2))
        slot_a, slot_b = np.where(swap, slot_2, slot_1), np.where(swap, slot_1, slot_2)
        kinds = PAIR_KIND[kind[slot_a], kind[slot_b]]
        world = first // n
        keys = pair_keys(kinds, world, slot_a, slot_b, self.batch, n)
        return keys, world * n + slot_a, world * n + slot_b

    def _overlap(self, first: np.ndarray, second: np.ndarray) -> np.ndarray:
        return (
            np.abs(self.fat_x[first] - self.fat_x[second])
            < self.fat_hx[first] + self.fat_hx[second]
        ) & (
            np.abs(self.fat_y[first] - self.fat_y[second])
            < self.fat_hy[first] + self.fat_hy[second]
        )

    def _dense(self, moved: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Every moved body against every slot of its world (rows of the (B, N) arrays)."""
        n = self.slots
        world = moved // n

        def rows(array: np.ndarray) -> np.ndarray:
            return np.take(array.reshape(-1, n), world, axis=0)

        hit = np.abs(rows(self.fat_x) - self.fat_x[moved][:, None]) < (
            rows(self.fat_hx) + self.fat_hx[moved][:, None]
        )
        hit &= np.abs(rows(self.fat_y) - self.fat_y[moved][:, None]) < (
            rows(self.fat_hy) + self.fat_hy[moved][:, None]
        )
        first, cols = np.divmod(np.flatnonzero(hit), n)  # 2-D nonzero is several times slower
        return moved[first], world[first] * n + cols

    def _sweep(self, moved: np.ndarray, present: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Sort and sweep: candidates are bodies whose left edge lies in a window."""
        n = self.slots
        bodies = np.flatnonzero(present & np.isfinite(self.fat_hx))
        half = self.fat_hx[bodies]
        # Bodies far wider than typical are tested densely, so that the sweep window
        # (which must span the widest body) stays narrow.
        typical = np.median(half)
        large = half > 8.0 * typical
        # One sorted axis for all worlds: offset each world by more than any body reaches
        # (large ones included), so a body's window never reaches into another world.
        spread = 2.0 * (np.abs(self.fat_x[bodies]).max() + half.max()) + 1.0
        first_parts, second_parts = [], []
        if large.any():
            big = bodies[large]
            same_world = (moved // n)[:, None] == (big // n)[None, :]
            f = np.broadcast_to(moved[:, None], same_world.shape)[same_world]
            s = np.broadcast_to(big[None, :], same_world.shape)[same_world]
            hit = self._overlap(f, s)
            first_parts.append(f[hit])
            second_parts.append(s[hit])
            # ... and the large moved bodies must see the small ones too.
            bodies, half = bodies[~large], half[~large]
        widest = 2.0 * half.max() if half.size else 0.0
        left = self.fat_x[bodies] - half
        order = np.argsort((bodies // n) * spread + left, kind="stable")
        sorted_bodies = bodies[order]
        sorted_keys = ((bodies // n) * spread + left)[order]
        m_world = (moved // n) * spread
        m_left = self.fat_x[moved] - self.fat_hx[moved]
        m_right = self.fat_x[moved] + self.fat_hx[moved]
        slack = 1e-9 * spread
        lo = np.searchsorted(sorted_keys, m_world + m_left - widest - slack, side="left")
        hi = np.searchsorted(sorted_keys, m_world + m_right + slack, side="right")
        counts = hi - lo
        total = int(counts.sum())
        owner = np.repeat(np.arange(moved.size), counts)
        start = np.cumsum(counts) - counts
        position = lo[owner] + (np.arange(total) - start[owner])
        f = moved[owner]
        s = sorted_bodies[position]
        hit = self._overlap(f, s) & (f // n == s // n)
        first_parts.append(f[hit])
        second_parts.append(s[hit])
        return np.concatenate(first_parts), np.concatenate(second_parts)


def plane_pairs(kind: np.ndarray, allowed: np.ndarray, batch: int) -> np.ndarray:
    """Sorted keys of every (body, plane) pair in every world, for the current slots."""
    slots = kind.size
    planes = np.flatnonzero(kind == 2)
    bodies = np.flatnonzero((kind == 0) | (kind == 1))
    if planes.size == 0 or bodies.size == 0:
        return np.zeros(0, np.int64)
    a, b = np.meshgrid(bodies, planes, indexing="ij")
    a, b = a.ravel(), b.ravel()
    ok = allowed[a, b]
    a, b = a[ok], b[ok]
    kinds = PAIR_KIND[kind[a], kind[b]]
    world = np.arange(batch)[:, None]
    keys = pair_keys(kinds[None, :], world, a[None, :], b[None, :], batch, slots).ravel()
    return np.sort(keys)
