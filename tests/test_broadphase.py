"""The broadphase: its candidate pairs are exactly the overlapping fat boxes, whichever
query it uses (dense or sort-and-sweep), and the work stays proportional to the contacts."""

import numpy as np
import pytest

import impulse2d as p2
from impulse2d.broadphase import Broadphase, decode_keys


def _random_boxes(rng: np.random.Generator, batch: int, slots: int, spread: float):
    """Fat boxes in ``batch`` worlds of ``slots`` bodies, a few of them very long."""
    total = batch * slots
    x, y = rng.uniform(-spread, spread, total), rng.uniform(-spread, spread, total)
    hx, hy = rng.uniform(0.05, 0.5, total), rng.uniform(0.05, 0.5, total)
    long = rng.random(total) < 0.02
    hx[long] = 50.0  # a long ground: the sweep must still see everything under it
    return x, y, hx, hy


def _brute_force(x, y, hx, hy, batch, slots):
    """Every pair of overlapping boxes in the same world, as a set of (flat a, flat b)."""
    pairs = set()
    for w in range(batch):
        s = slice(w * slots, (w + 1) * slots)
        ox = np.abs(x[s, None] - x[None, s]) < hx[s, None] + hx[None, s]
        oy = np.abs(y[s, None] - y[None, s]) < hy[s, None] + hy[None, s]
        i, j = np.nonzero(np.triu(ox & oy, 1))
        pairs |= {(w * slots + a, w * slots + b) for a, b in zip(i, j, strict=True)}
    return pairs


@pytest.mark.parametrize("dense_limit", [10**9, 0])  # all dense / all sort-and-sweep
def test_pairs_are_exactly_the_overlapping_boxes(dense_limit):
    """Dense and sweep queries both find exactly the overlapping pairs, across worlds."""
    rng = np.random.default_rng(3)
    batch, slots = 3, 120
    x, y, hx, hy = _random_boxes(rng, batch, slots, spread=6.0)
    broad = Broadphase(batch, slots, dense_limit=dense_limit)
    kind = np.zeros(slots, np.int8)  # all circles
    allowed = ~np.eye(slots, dtype=bool)
    everyone = np.arange(batch * slots)
    present = np.ones(batch * slots, dtype=bool)
    zero = np.zeros(batch * slots)
    keys, a, b = broad.update(x, y, hx, hy, zero, zero, everyone, present, allowed, kind)
    found = set(zip(a.tolist(), b.tolist(), strict=True))
    assert found == _brute_force(x, y, hx, hy, batch, slots)
    assert np.all(np.diff(keys) > 0)  # sorted, unique
    np.testing.assert_array_equal(np.stack(decode_keys(keys, batch, slots)), np.stack([a, b]))

    # Move a third of the bodies: only they are re-queried, and the result is still exact.
    moved = rng.choice(batch * slots, batch * slots // 3, replace=False)
    x2, y2 = x.copy(), y.copy()
    x2[moved] += rng.normal(0.0, 2.0, moved.size)
    y2[moved] += rng.normal(0.0, 2.0, moved.size)
    before = broad.updates
    keys, a, b = broad.update(x2, y2, hx, hy, zero, zero, everyone, present, allowed, kind)
    assert broad.updates - before <= moved.size
    # Fat boxes of bodies that did not leave theirs keep their old centres: compare with
    # the boxes the broadphase holds.
    held = _brute_force(broad.fat_x, broad.fat_y, broad.fat_hx, broad.fat_hy, batch, slots)
    assert set(zip(a.tolist(), b.tolist(), strict=True)) == held


def _rain(count: int, seed: int = 0) -> p2.World:
    """``count`` small circles and boxes spread over a wide floor, falling."""
    rng = np.random.default_rng(seed)
    world = p2.World(sleeping=False)
    world.add(p2.Plane())
    width = count * 0.6  # keeps the density the same for every count
    for i in range(count):
        position = (rng.uniform(-width / 2, width / 2), rng.uniform(0.5, 6.0))
        if i % 2:
            world.add(p2.Circle(position=position, radius=0.2))
        else:
            world.add(p2.Box(position=position, width=0.4, height=0.3, angle=rng.uniform(0, 3)))
    return world


def test_pair_count_grows_linearly_with_scene_size():
    """At the same density, 4x the bodies gives about 4x the candidate pairs (not 16x), and
    each step re-queries only a fraction of the bodies once things settle."""
    counts = {}
    for count in (250, 1000):
        world = _rain(count)
        for _ in range(90):
            world.step(1 / 60)
        counts[count] = world._broadphase.keys.size
        before = world._broadphase.updates
        world.step(1 / 60)
        assert world._broadphase.updates - before < count / 2
    assert counts[1000] / counts[250] < 6.0
