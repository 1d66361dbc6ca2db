"""Graph colouring of a world's two-point manifolds, and their constraints packed once a step.

A large world's solve and relax passes spend their time on two-point manifolds (a box on
a box, a box on a static box): Gauss-Seidel over them in narrowphase order is a chain of
dependent scalar solves. Box2D v3 colours them instead: manifolds of one colour share no
body that moves, so they are independent and solved side by side, in vector lanes
(``lanes.py``). Colouring is greedy and done again every step inside one world (never
across worlds: a world steps the same alone and in a batch). A body that cannot move
this step (fixed, kinematic, asleep) is never written by the solver, so any number of
a colour's manifolds may share it.

*Which colours.* Manifolds between two moving bodies take the lowest colour free for
both, among the first ``DYNAMIC_COLOURS``; manifolds with a body that cannot move take
the highest colour free for their moving body, from ``COLOURS - 1`` down to 1. Colours
are solved in ascending order, so contacts with the immovable bodies are solved after
the others and hold best (in Gauss-Seidel the last row solved holds exactly): the rule
by which ``solver.sweep`` solves points against planes last, and Box2D's (its static
colours are built from the end "to get higher priority"). What finds no colour (a body
touching more than ``DYNAMIC_COLOURS`` others) stays with the rest of the points,
solved in order after the colours (Box2D's overflow).

*Which manifolds.* Exactly two points, of two bodies neither of which is a plane, with
one normal (a box on a box). One-point contacts (discs), pairs of more points and
points against planes keep ``solver.sweep``'s order and its rules. A world is coloured
only from ``ctx[COLOUR_FROM]`` points a step up (``COLOUR_FROM_POINTS``): below that,
the pool table's 30-point break for one, plain order is faster (``docs/solver_layout.md``).

*The constraint columns* ``con[field, m]`` (``workspace.CON_F``; field-major: a field's
values of a colour lie side by side), written here once a step, for manifold ``m`` in
colour order: its normal, friction, step inverse masses and softness, and per point
``p`` at ``point_base(p)`` its separation at the step start, its Jacobian's cross terms
and masses, its anchors, and what the solver accumulates over the step: from ``pack`` to
``unpack`` a coloured point lives in ``con``, not in its point row (``lanes.py`` warm
starts, solves and moves its anchors there).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ._jit import inline, kernel
from .workspace import (
    AGAINST_PLANE,
    APPROACH_SPEED,
    BIAS_RATE,
    CBIAS_RATE,
    CFRICTION,
    CIIA,
    CIIB,
    CIMA,
    CIMB,
    CIMPULSE_SCALE,
    CMASS_SCALE,
    CNX,
    CNY,
    COLOURS,
    CON_F,
    DRIFT,
    FOLLOW0,
    GROSS_J,
    IIA,
    IIB,
    IMA,
    IMB,
    IMPULSE_SCALE,
    IN_COLOUR,
    KEEP,
    MASS_SCALE,
    MAX_J,
    MIXED_FRICTION,
    MIXED_RESTITUTION,
    MOVABLE,
    NORMAL_J,
    NORMAL_MASS,
    NX,
    NY,
    PBOUNCES,
    PDRIFT,
    PER_FOLLOW,
    PER_POINT,
    PGROSS_J,
    PKEEP,
    PMAX_J,
    PNORMAL_J,
    PNORMAL_MASS,
    POINT0,
    PRAX,
    PRAY,
    PRBX,
    PRBY,
    PRNA,
    PRNB,
    PRTA,
    PRTB,
    PSEP0,
    PSTEP_J,
    PTANGENT_J,
    PTANGENT_MASS,
    RAX,
    RAY,
    RBX,
    RBY,
    RNA,
    RNB,
    RTA,
    RTB,
    SEP0,
    STEP_J,
    TANGENT_J,
    TANGENT_MASS,
)

DYNAMIC_COLOURS = 24  # of which manifolds between two moving bodies may take the first
# A world's points a step from which it is coloured (see above); ``Settings`` reads it
# when it makes a step context, so a test or a benchmark may set it before a world steps.
COLOUR_FROM_POINTS = 128


@inline
def point_base(p):
    """The first constraint column of point ``p`` (0 or 1) of a manifold."""
    return POINT0 + p * PER_POINT


@inline
def follow_base(p):
    """The first of point ``p``'s columns that only ``follow_bodies`` reads."""
    return FOLLOW0 + p * PER_FOLLOW


@inline
def manifold_end(ids, n, start) -> int:
    """The end of the pair of points that starts at ``start`` (a pair's points are
    neighbours)."""
    end = start + 1
    while end < n and ids[end, 0] == ids[start, 0] and ids[end, 1] == ids[start, 1]:
        end += 1
    return end


@inline
def pair_at(others, p, end) -> int:
    """The first point of the ``p``-th pair a plain pass visits: in a coloured world
    ``others[p]`` (its pairs that are not coloured, then ``n``:
    ``colouring.colour_manifolds``), else ``end``, the end of the pair before (every
    pair, in order; ``others`` is empty)."""
    return others[p] if others.shape[0] else end


@inline
def colourable(terms, points, ids, n, start, end) -> bool:
    """Two points of two bodies, not against a plane, one normal, one of them moving."""
    if end - start != 2 or points[start, AGAINST_PLANE] == 1.0:
        return False
    a, b = ids[start, 0], ids[start, 1]
    same_normal = (
        points[start, NX] == points[start + 1, NX] and points[start, NY] == points[start + 1, NY]
    )
    return same_normal and (terms[a, MOVABLE] != 0.0 or terms[b, MOVABLE] != 0.0)


@inline
def free_colour(taken, lowest, highest, step) -> int:
    """The first colour from ``lowest`` towards ``highest`` (``step`` +1 or -1, both ends
    included) whose bit is clear in ``taken``, or -1."""
    c = lowest
    while (c - highest) * step <= 0:
        if (taken >> c) & 1 == 0:
            return c
        c += step
    return -1


@kernel
def colour_manifolds(terms, points, ids, n, masks, found, colours, order, starts,
                     others) -> int:  # fmt: skip
    """Colour the world's colourable manifolds (module docstring); returns how many.

    ``masks`` (N,) int64: scratch, the colours each body is in; ``found``, ``colours``
    (M,): scratch, each coloured manifold's first point and colour in narrowphase order;
    ``order`` (M,): the first point of each manifold in colour order; ``starts``
    (COLOURS + 1,): where each colour begins in ``order``; ``others`` (at least as long
    as the manifolds not coloured, plus one): the first point of each of those in
    narrowphase order, then ``n`` (the plain passes walk it: in a large world most
    manifolds are coloured, and scanning all the points to skip them cost more than the
    passes over the others). Every point not against a plane gets ``AGAINST_PLANE`` =
    ``IN_COLOUR`` if its manifold is coloured, else 0."""
    masks[:] = 0
    count = 0
    listed = 0
    start = 0
    while start < n:
        end = manifold_end(ids, n, start)
        colour = -1
        if colourable(terms, points, ids, n, start, end):
            a, b = ids[start, 0], ids[start, 1]
            moves_a, moves_b = terms[a, MOVABLE] != 0.0, terms[b, MOVABLE] != 0.0
            taken = (masks[a] if moves_a else 0) | (masks[b] if moves_b else 0)
            if moves_a and moves_b:
                colour = free_colour(taken, 0, DYNAMIC_COLOURS - 1, 1)
            else:
                colour = free_colour(taken, COLOURS - 1, 1, -1)
            if colour >= 0:
                bit = 1 << colour
                masks[a] |= bit if moves_a else 0
                masks[b] |= bit if moves_b else 0
                found[count], colours[count] = start, colour
                count += 1
        if colour < 0:
            others[listed] = start
            listed += 1
        for k in range(start, end):
            if points[k, AGAINST_PLANE] != 1.0:
                points[k, AGAINST_PLANE] = IN_COLOUR if colour >= 0 else 0.0
        start = end
    others[listed] = n
    sort_by_colour(found, colours, count, order, starts)
    return count


@kernel
def sort_by_colour(found, colours, count, order, starts) -> None:
    """A counting sort of the first ``count`` manifolds into colour order (stable: a
    colour keeps the narrowphase order)."""
    starts[:] = 0
    for m in range(count):
        starts[colours[m] + 1] += 1
    for c in range(COLOURS):
        starts[c + 1] += starts[c]
    for m in range(count):  # starts[c] advances past each manifold placed ...
        c = colours[m]
        order[starts[c]] = found[m]
        starts[c] += 1
    for c in range(COLOURS, 0, -1):  # ... and is moved back to where colour c begins
        starts[c] = starts[c - 1]
    starts[0] = 0


class Coloured(NamedTuple):
    """A world's coloured manifolds, cut from its scratch by ``colour_arrays``."""

    con: np.ndarray  # (CON_F, M) their constraints (workspace.CON_F)
    lanes: np.ndarray  # (LANE_F, M) a colour's bodies gathered (lanes.py)
    order: np.ndarray  # (M,) each manifold's first point, in colour order
    body_a: np.ndarray  # (M,) each manifold's body A, in colour order (``pair_bodies``)
    body_b: np.ndarray  # (M,) ... and its body B
    others: np.ndarray  # (2M,) the first point of each manifold not coloured, ascending,
    # then the world's point count ``n`` (``colour_manifolds``)
    starts: np.ndarray  # (COLOURS + 1,) where each colour begins in ``order``
    found: np.ndarray  # (M,) scratch of the colouring: first points in narrowphase order
    colours: np.ndarray  # (M,) ... and their colours
    masks: np.ndarray  # (N,) ... and the colours each body is in


@inline
def colour_arrays(colour_floats, colour_ints):
    """``Scratch.colour_floats`` and ``colour_ints`` (``workspace.colour_sizes``) cut into
    a ``Coloured``: ``con`` and ``lanes`` from the floats, then ``order``, ``found``,
    ``colours``, ``body_a``, ``body_b``, ``others``, ``starts`` and ``masks`` from the
    ints."""
    m = colour_floats.shape[1]
    con, lanes = colour_floats[:CON_F], colour_floats[CON_F:]  # rows: no reshape (on a GPU
    # a world's scratch is strided, which numba cannot reshape)
    order, found, colours = colour_ints[:m], colour_ints[m : 2 * m], colour_ints[2 * m : 3 * m]
    body_a, body_b = colour_ints[3 * m : 4 * m], colour_ints[4 * m : 5 * m]
    others = colour_ints[5 * m : 7 * m]
    at = 7 * m + COLOURS + 1
    starts, masks = colour_ints[7 * m : at], colour_ints[at:]
    return Coloured(con, lanes, order, body_a, body_b, others, starts, found, colours, masks)


@kernel
def pair_bodies(ids, order, count, body_a, body_b) -> None:
    """The two bodies of each of the ``count`` coloured manifolds, in colour order: the
    passes read them from these two arrays front to back, not from the point rows of
    ``order``, whose rows lie wherever the narrowphase put them."""
    for m in range(count):
        body_a[m], body_b[m] = ids[order[m], 0], ids[order[m], 1]


@kernel
def colour_step(terms, points, ids, n, colour_floats, colour_ints, threshold) -> int:
    """Colour the world's manifolds, list their bodies and pack them
    (``colour_manifolds``, ``pair_bodies``, ``pack``); returns how many were coloured."""
    c = colour_arrays(colour_floats, colour_ints)
    count = colour_manifolds(terms, points, ids, n, c.masks, c.found, c.colours, c.order,
                             c.starts, c.others)  # fmt: skip
    pair_bodies(ids, c.order, count, c.body_a, c.body_b)
    pack(points, c.order, count, c.con, threshold)
    return count


@kernel
def unpack_step(points, colour_floats, colour_ints, count) -> None:
    """``unpack`` of the world's ``count`` coloured manifolds."""
    c = colour_arrays(colour_floats, colour_ints)
    unpack(points, c.order, count, c.con)


@kernel
def pack(points, order, count, con, threshold) -> None:
    """``con`` for manifolds ``0:count`` from their points, as the step's preparation
    left them: what holds over the step, the Jacobians, and the impulses carried from
    the last step (what the solver accumulates over the step starts here); a point may
    bounce if it closes faster than ``threshold`` (``contacts.follow_bodies``)."""
    for m in range(count):
        k = order[m]
        con[CNX, m], con[CNY, m] = points[k, NX], points[k, NY]
        con[CFRICTION, m] = points[k, MIXED_FRICTION]
        con[CIMA, m], con[CIMB, m] = points[k, IMA], points[k, IMB]
        con[CIIA, m], con[CIIB, m] = points[k, IIA], points[k, IIB]
        con[CBIAS_RATE, m] = points[k, BIAS_RATE]
        con[CMASS_SCALE, m] = points[k, MASS_SCALE]
        con[CIMPULSE_SCALE, m] = points[k, IMPULSE_SCALE]
        for p in range(2):
            base = point_base(p)
            con[base + PSEP0, m] = points[k + p, SEP0]
            con[base + PNORMAL_J, m] = points[k + p, NORMAL_J]
            con[base + PTANGENT_J, m] = points[k + p, TANGENT_J]
            con[base + PSTEP_J, m] = points[k + p, STEP_J]
            con[base + PMAX_J, m] = points[k + p, MAX_J]
            con[base + PGROSS_J, m] = points[k + p, GROSS_J]
            follow = follow_base(p)
            con[follow + PRAX, m], con[follow + PRAY, m] = points[k + p, RAX], points[k + p, RAY]
            con[follow + PRBX, m], con[follow + PRBY, m] = points[k + p, RBX], points[k + p, RBY]
            con[follow + PKEEP, m] = points[k + p, KEEP]
            bounces = points[k + p, MIXED_RESTITUTION] > 0.0
            bounces &= points[k + p, APPROACH_SPEED] < -threshold
            con[follow + PBOUNCES, m] = 1.0 if bounces else 0.0
            con[follow + PDRIFT, m] = points[k + p, DRIFT]
    refresh_jacobians(points, order, count, con)


@kernel
def refresh_jacobians(points, order, count, con) -> None:
    """Each point's Jacobian cross terms and masses into ``con``, as the step begins
    (``lanes.follow_coloured`` keeps them after that)."""
    for m in range(count):
        for p in range(2):
            k, base = order[m] + p, point_base(p)
            con[base + PRNA, m], con[base + PRNB, m] = points[k, RNA], points[k, RNB]
            con[base + PRTA, m], con[base + PRTB, m] = points[k, RTA], points[k, RTB]
            con[base + PNORMAL_MASS, m] = points[k, NORMAL_MASS]
            con[base + PTANGENT_MASS, m] = points[k, TANGENT_MASS]


@kernel
def unpack(points, order, count, con) -> None:
    """What the substeps accumulated back into the points (restitution, the contact
    cache and the events read it there)."""
    for m in range(count):
        for p in range(2):
            k, base = order[m] + p, point_base(p)
            points[k, NORMAL_J] = con[base + PNORMAL_J, m]
            points[k, TANGENT_J] = con[base + PTANGENT_J, m]
            points[k, STEP_J] = con[base + PSTEP_J, m]
            points[k, MAX_J] = con[base + PMAX_J, m]
            points[k, GROSS_J] = con[base + PGROSS_J, m]
            points[k, DRIFT] = con[follow_base(p) + PDRIFT, m]
