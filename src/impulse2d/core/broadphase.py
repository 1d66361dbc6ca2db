"""Broadphase: the pairs of one world worth a narrowphase test, by sort and sweep.

Each body gets a box: its axis-aligned bounding box grown on every side by how far it can
travel this step (``(|vx| + |vy| + R |w|) dt``) and by half its speculative distance, so
two boxes overlap whenever the narrowphase could make a contact. The boxes are sorted by
their left edge and swept: a body is tested only against those whose left edge lies
before its right edge, so the cost is ``O(n + pairs)`` rather than ``O(n^2)``. The sorted
order is kept from step to step (``state.SAP_ORDER``) and re-sorted by insertion, which
costs ``O(n)`` when little has changed: bodies move a little per step.

A pair is a candidate if the boxes overlap, at least one body moves this step and at least
one is dynamic. Planes are infinite and not in the sweep: every moving dynamic body is
paired with every plane of its world (there are few).

The pairs come out in a canonical order, by the slot of A and then of B, where a pair is
ordered so that ``kind(A) <= kind(B)`` (a slot before a higher one of the same kind). The
sweep's own order depends on history; the canonical one does not, so the solver meets
contacts in the same order however the world got to where it is (restored, alone or in a
batch). The counting sort that produces it costs ``O(n + pairs)``.
"""

from __future__ import annotations

import numpy as np

from . import context
from ._jit import inline, kernel
from .state import DYNAMIC, ENABLED, PLANE, RESTITUTION, SAP_ORDER
from .workspace import (
    BOTTOM,
    LEFT,
    MOVABLE,
    MOVING,
    PUSHED,
    REACH,
    RIGHT,
    SWEPT_BOTTOM,
    SWEPT_FLAGS,
    SWEPT_LEFT,
    SWEPT_RIGHT,
    SWEPT_TOP,
    TOP,
)


@kernel
def sort_by_left_edge(order, terms) -> None:
    """Insertion sort of a permutation of the slots by their boxes' left edges."""
    for p in range(1, order.size):
        slot = order[p]
        key = terms[slot, LEFT]
        q = p - 1
        while q >= 0 and terms[order[q], LEFT] > key:
            order[q + 1] = order[q]
            q -= 1
        order[q + 1] = slot


@inline
def add_pair(pairs, count, a, b, shapes) -> int:
    """Append the pair ordered so that kind(A) <= kind(B); returns the new count (which
    may pass the capacity: then only the count is kept, and the step asks for room)."""
    ka, kb = shapes[a, 0], shapes[b, 0]
    if kb < ka or (kb == ka and b < a):
        a, b = b, a
    if count < pairs.shape[0]:
        pairs[count, 0] = a
        pairs[count, 1] = b
    return count + 1


# A world of at most this many slots is swept in place (``sweep_small``): the copy into
# sweep order and the bisections pay off only when a box overlaps many along x.
SMALL_WORLD = 64


@inline
def sweep_small(shapes, terms, order, pairs) -> int:
    """The plain sweep, reading the boxes where they are: for each box in left-edge
    order, the boxes after it up to the first that starts past its right edge, paired
    where they overlap along y too, one of the two moves and one is dynamic."""
    n, count = order.size, 0
    for p in range(n):
        i = order[p]
        right = terms[i, RIGHT]
        if terms[i, LEFT] == np.inf:
            break  # not in the broadphase (they sort last)
        moving_i, dynamic_i = terms[i, MOVING] == 1.0, shapes[i, 1] == DYNAMIC
        for q in range(p + 1, n):
            j = order[q]
            if terms[j, LEFT] >= right:
                break
            if terms[j, BOTTOM] < terms[i, TOP] and terms[i, BOTTOM] < terms[j, TOP]:
                moving = moving_i or terms[j, MOVING] == 1.0
                if moving and (dynamic_i or shapes[j, 1] == DYNAMIC):
                    count = add_pair(pairs, count, i, j, shapes)
    return count


@kernel
def sweep(body_i, shapes, w, terms, swept, near, pairs) -> int:
    """Sort and sweep the world's circles and boxes; returns the number of pairs.

    Two boxes overlap when ``left_a < right_b``, ``left_b < right_a`` and the same on y.
    Sorted by left edge, ``left_a <= left_b``, so the first holds and the sweep stops at the
    first ``left_b >= right_a``. The test is symmetric in a and b, so the pairs found do not
    depend on the order the sweep remembered.

    The inner loop reads the boxes copied into ``swept`` in sweep order (a box in a tall
    stack overlaps a hundred others along x); ``near`` (N + 1,) is int scratch."""
    order = body_i[w, :, SAP_ORDER]
    sort_by_left_edge(order, terms)
    n = order.size
    if n <= SMALL_WORLD:
        return sweep_small(shapes, terms, order, pairs)
    for p in range(n):
        i = order[p]
        swept[SWEPT_LEFT, p], swept[SWEPT_RIGHT, p] = terms[i, LEFT], terms[i, RIGHT]
        swept[SWEPT_BOTTOM, p], swept[SWEPT_TOP, p] = terms[i, BOTTOM], terms[i, TOP]
        moving = 1.0 if terms[i, MOVING] == 1.0 else 0.0
        swept[SWEPT_FLAGS, p] = moving + (2.0 if shapes[i, 1] == DYNAMIC else 0.0)
    lefts, bottoms, tops = swept[SWEPT_LEFT], swept[SWEPT_BOTTOM], swept[SWEPT_TOP]
    flags = swept[SWEPT_FLAGS]
    count = 0
    # Backwards, so that the first moving box after this one is known (``ahead``): a box
    # that does not move pairs only with moving ones, and when none starts before its
    # right edge it has no pair and is passed over (a resting pile's boxes, nearly all).
    # The order the pairs are found in does not matter: they are sorted after.
    ahead = n
    for p in range(n - 1, -1, -1):
        if lefts[p] == np.inf:
            continue  # not in the broadphase (they sort last)
        right, bottom, top = swept[SWEPT_RIGHT, p], bottoms[p], tops[p]
        moving_a, dynamic_a = flags[p] == 1.0 or flags[p] == 3.0, flags[p] >= 2.0
        if moving_a:
            ahead = p
        elif ahead == n or lefts[ahead] >= right:
            continue
        # The boxes that start before this one's right edge end at the first that does
        # not (bisection); of those, the ones that overlap along y are listed in ``near``
        # without a branch (each is written, the count moves on only past an overlap),
        # then paired. A branch on each overlap, rare and unpredictable, made the loop
        # three times as long in a tall stack.
        lo, hi = p + 1, n
        while lo < hi:
            mid = (lo + hi) >> 1
            if lefts[mid] < right:
                lo = mid + 1
            else:
                hi = mid
        found = 0
        for q in range(p + 1, lo):
            near[found] = q
            found += 1 if (bottoms[q] < top) & (bottom < tops[q]) else 0
        for k in range(found):
            q = near[k]
            moving = moving_a or flags[q] == 1.0 or flags[q] == 3.0
            if moving and (dynamic_a or flags[q] >= 2.0):
                count = add_pair(pairs, count, order[p], order[q], shapes)
    return count


@kernel
def plane_pairs(body_i, shapes, w, terms, pairs, count) -> int:
    """Every moving dynamic body with every plane of the world."""
    for p in range(shapes.shape[0]):
        if shapes[p, 0] != PLANE or body_i[w, p, ENABLED] == 0:
            continue
        for i in range(shapes.shape[0]):
            if terms[i, MOVABLE] == 1.0 and shapes[i, 0] != PLANE:
                count = add_pair(pairs, count, i, p, shapes)
    return count


@kernel
def canonical_order(pairs, count, scratch, buckets) -> None:
    """Sort the first ``count`` pairs by (A, B): counting sort by A, then insertion sort
    of each A's (few) partners by B."""
    n = buckets.size - 1
    buckets[:] = 0
    for k in range(count):
        buckets[pairs[k, 0] + 1] += 1
    for i in range(n):
        buckets[i + 1] += buckets[i]
    for k in range(count):
        a = pairs[k, 0]
        at = buckets[a]
        scratch[at, 0], scratch[at, 1] = a, pairs[k, 1]
        buckets[a] = at + 1
    start = 0
    for a in range(n):
        end = buckets[a]  # after the placing pass: where A's run ends
        for p in range(start + 1, end):
            partner = scratch[p, 1]
            q = p - 1
            while q >= start and scratch[q, 1] > partner:
                scratch[q + 1, 1] = scratch[q, 1]
                q -= 1
            scratch[q + 1, 1] = partner
        start = end
    for k in range(count):
        pairs[k, 0], pairs[k, 1] = scratch[k, 0], scratch[k, 1]


@kernel
def pushed_reach(body, shapes, w, ctx, terms, pairs, count) -> None:
    """Each body's ``PUSHED``: how fast it may go within the step, counting the bodies it
    may touch. A body struck by another can leave at up to ``(1 + e)`` times their
    closing speed (``e`` the larger restitution, or their product if that is larger:
    no mixing rule gives more), and an overlap pushes it out at up to the push speed;
    a body near nothing keeps its own ``REACH``.
    A plane's contacts with a body are made from this: a light body struck towards a
    plane by a fast one must find the plane there (planes are infinite, so a far
    speculative point costs one point and stops nothing it should not)."""
    push = ctx[context.PUSH_SPEED]
    for i in range(shapes.shape[0]):
        terms[i, PUSHED] = terms[i, REACH] if terms[i, MOVABLE] == 1.0 else 0.0
    for k in range(min(count, pairs.shape[0])):
        a, b = pairs[k, 0], pairs[k, 1]
        ea, eb = body[w, a, RESTITUTION], body[w, b, RESTITUTION]
        closing = (1.0 + max(ea, eb, ea * eb)) * (terms[a, REACH] + terms[b, REACH])
        for i in (a, b):
            if terms[i, MOVABLE] == 1.0:
                terms[i, PUSHED] = max(terms[i, PUSHED], terms[i, REACH] + push + closing)


@kernel
def find_pairs(body, body_i, shapes, w, ctx, terms, swept, pairs, scratch, buckets) -> int:
    """The candidate pairs of world ``w`` in canonical order; returns their number (more
    than ``pairs`` holds means the step needs more room). ``swept`` is the sweep's
    scratch (``workspace.SWEPT_F``, N)."""
    count = sweep(body_i, shapes, w, terms, swept, buckets, pairs)  # buckets: free till sorting
    pushed_reach(body, shapes, w, ctx, terms, pairs, count)
    count = plane_pairs(body_i, shapes, w, terms, pairs, count)
    if count <= pairs.shape[0]:
        canonical_order(pairs, count, scratch, buckets)
    return count
