"""Sleeping by islands, as the tutorial's extra asks and Box2D does; waking.

A dynamic body whose speed stays below ``sleep_speed`` (with rotation counted as the
speed of its bounding circle's rim, ``R |w|``) accumulates ``sleep_time``. An *island*
is a set of moving dynamic bodies joined by contact points or springs; an island falls
asleep when all its bodies have been slow for ``time_to_sleep`` seconds, and wakes as a
whole when something that moves touches any of its bodies. Sleeping bodies cost
nothing: their pairs are skipped, and they are neither integrated nor solved; a world in
which everything sleeps is skipped altogether.

Islands are found per world by union-find over this step's contact points, with the
smallest slot as each island's root, which is also its id while it sleeps. Putting a
single slow body to sleep while a neighbour still moves would leave it floating when the
neighbour slides away; islands prevent that.
"""

from __future__ import annotations

from . import context
from ._jit import kernel
from .integrate import spring_acts
from .state import (
    AWAKE,
    BODY_A,
    BODY_B,
    CONTACT_COUNT,
    DYNAMIC,
    ENABLED,
    ISLAND,
    OMEGA,
    SLEEP_TIME,
    VX,
    VY,
)
from .workspace import MOVABLE, MOVING, SPEED


@kernel
def wake_island(body, body_i, shapes, w, slot) -> bool:
    """Wake a sleeping dynamic body with its whole island; returns whether it slept."""
    if body_i[w, slot, AWAKE] == 1 or body_i[w, slot, ENABLED] == 0:
        return False
    if shapes[slot, 1] != DYNAMIC:
        return False
    island = body_i[w, slot, ISLAND]
    for i in range(shapes.shape[0]):
        member = i == slot or (island >= 0 and body_i[w, i, ISLAND] == island)
        if member and body_i[w, i, AWAKE] == 0:
            body_i[w, i, AWAKE] = 1
            body_i[w, i, ISLAND] = -1
            body[w, i, SLEEP_TIME] = 0.0
    return True


@kernel
def wake_neighbours(body, body_i, shapes, contact_i, world_i, w, slot) -> None:
    """Wake everything that touched ``slot`` at the last step (it is leaving, or moved
    by hand, and what rested on it must not float)."""
    for j in range(world_i[w, CONTACT_COUNT]):
        a, b = contact_i[w, j, BODY_A], contact_i[w, j, BODY_B]
        if a == slot:
            wake_island(body, body_i, shapes, w, b)
        elif b == slot:
            wake_island(body, body_i, shapes, w, a)


@kernel
def wake_touched(body, body_i, shapes, spring, ends, w, terms, ids, n) -> bool:
    """Wake the islands that a moving body touches (a contact point or a spring);
    returns whether anything woke."""
    woke = False
    for k in range(n + ends.shape[0]):
        if k < n:
            a, b = ids[k, 0], ids[k, 1]
        else:
            a, b = ends[k - n, 0], ends[k - n, 1]
            if not spring_acts(body_i, spring, ends, w, k - n):
                continue
        if terms[a, MOVING] == terms[b, MOVING]:
            continue  # both move, or neither (nothing moving touches a sleeper)
        sleeper = b if terms[a, MOVING] == 1.0 else a
        woke |= wake_island(body, body_i, shapes, w, sleeper)
    return woke


@kernel
def _root(parents, i) -> int:
    while parents[i] != i:
        parents[i] = parents[parents[i]]  # path halving
        i = parents[i]
    return i


@kernel
def _join(parents, a, b) -> None:
    ra, rb = _root(parents, a), _root(parents, b)
    if ra < rb:
        parents[rb] = ra  # the smallest slot stays the root: a deterministic island id
    elif rb < ra:
        parents[ra] = rb


@kernel
def update_sleep(
    body, body_i, spring, ends, w, ctx, terms, ids, n, parents, blocked, moving, count
) -> None:  # fmt: skip
    """Accumulate slow time; put islands that have all been slow long enough to sleep.
    ``moving[:count]`` are the slots of the bodies that moved (``integrate.list_moving``):
    only they can grow slow time, and islands are joined only when one of them may sleep.

    Slowness uses the step's speed bound ``|vx| + |vy| + R |w|`` (a little stricter than
    the speed itself). Islands join bodies by every narrowphase point, touching or about
    to, not only those that pushed: contacts between bodies at rest push nothing, and
    islands cut along them would sleep in pieces, each woken again by its neighbour."""
    dt, limit = ctx[context.DT], ctx[context.TIME_TO_SLEEP]
    anyone = False
    for k in range(count):
        i = moving[k]
        if terms[i, MOVABLE] == 1.0:
            slow = terms[i, SPEED] < ctx[context.SLEEP_SPEED]
            body[w, i, SLEEP_TIME] = body[w, i, SLEEP_TIME] + dt if slow else 0.0
            anyone |= body[w, i, SLEEP_TIME] >= limit
    if not anyone:
        return
    # Only movable bodies are joined, roots and blocked, so only their slots are set up
    # and walked (in slot order, as the list is).
    for k in range(count):
        i = moving[k]
        parents[i], blocked[i] = i, 0
    for k in range(n):
        a, b = ids[k, 0], ids[k, 1]
        if terms[a, MOVABLE] == 1.0 and terms[b, MOVABLE] == 1.0:
            _join(parents, a, b)
    for k in range(ends.shape[0]):
        a, b = ends[k, 0], ends[k, 1]
        if spring_acts(body_i, spring, ends, w, k) and terms[a, MOVABLE] == 1.0:
            if terms[b, MOVABLE] == 1.0:
                _join(parents, a, b)
    for k in range(count):
        i = moving[k]
        if terms[i, MOVABLE] == 1.0 and body[w, i, SLEEP_TIME] < limit:
            blocked[_root(parents, i)] = 1
    for k in range(count):
        i = moving[k]
        if terms[i, MOVABLE] == 1.0 and blocked[_root(parents, i)] == 0:
            body_i[w, i, AWAKE] = 0
            body_i[w, i, ISLAND] = _root(parents, i)
            body[w, i, VX] = body[w, i, VY] = body[w, i, OMEGA] = 0.0
