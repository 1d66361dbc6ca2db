"""Scratch memory for a world's step: per-body step terms, candidate pairs, contact points.

None of this is state: a step writes it before reading it. On the CPU it lives in two
arrays with one row per *chunk* of worlds (the worlds one thread steps one after the
other), so a batch of a thousand worlds needs only a few rows, and ``views`` cuts a row
into the named 2-D arrays below (a ``Scratch``): two arrays cost a compiled call less to
take than ten. The GPU keeps the parts apart, a row per world (``part_shapes``,
``scratch_row``), each with the world axis innermost, which a reshape could not cut.
Capacities grow when a world needs more (``runner``).

Body terms ``terms`` (N, TERMS) float64, for the current step:

* ``MOVING`` 1.0 if the body moves this step (awake and enabled), ``MOVABLE`` 1.0 if it is
  also dynamic (pushed by contacts and forces);
* ``STEP_INV_MASS``, ``STEP_INV_MOMENT``: the inverse mass and moment if movable, else 0;
* ``ACCEL_X``, ``ACCEL_Y``, ``ACCEL_W``: ``h`` times the acceleration from gravity and the
  applied force and torque;
* ``ROLL_H``: ``h`` times the rolling resistance;
* ``SPEED``: a bound on the speed of any point of the body, ``|vx| + |vy| + R |w|`` (m/s),
  what sleeping compares; ``REACH``: that plus what gravity, forces and springs can add
  within the step, what the contacts are made from; ``PUSHED``: that plus what the bodies
  it may touch this step can give it, what its contacts with planes are made from;
* ``HALF_SPEC``: half the body's speculative distance;
* ``X0``, ``Y0``, ``ANGLE0``: its pose at the start of the step;
* ``LEFT``, ``RIGHT``, ``BOTTOM``, ``TOP``: its broadphase box, the shape's axis-aligned
  box grown by how far it can travel and half its speculative distance (``LEFT`` +inf
  when it is not in the broadphase).

The broadphase's sweep ``swept`` (SWEPT_F, N) float64: the boxes again, in the order the
sweep takes them, one array per field (its inner loop then reads consecutive numbers).
The solver's body states ``states`` (N, STATE_F) float64: a coloured world's passes
gather from and scatter to these rows, not the bodies' 30 columns (``lanes.py``).
The moving bodies ``moving`` (N,) int64: the slots of the bodies that move this step
(``MOVING``), in slot order, as many as ``integrate.list_moving`` returns. The loops
over bodies inside the substeps and at the step's end walk this list, so a sleeping
body, a fixed one or a free slot costs them nothing (Box2D moves its awake bodies into
a set of their own; here a body keeps the slot the API and the batch index it by, and
the list is the awake set).

Points ``points`` (C, POINT_F) float64 and ``point_ids`` (C, 3) int64 (body A, body B,
feature), one row per contact point of the step, sorted by (A, B, feature):

* from the narrowphase: the unit normal ``NX``, ``NY`` (from A to B), the anchors
  ``RAX``, ``RAY``, ``RBX``, ``RBY`` (offsets of the point from A's and B's centres) and
  ``SEP0``, the separation along the normal (m, < 0: overlap);
* from the contact preparation (``contacts.py``): effective masses, mixed materials,
  softness, the approach speed and acceleration along the normal, the Jacobian's cross
  terms ``rA x n`` ... and the step inverse masses;
* from the solver: accumulated impulses, the impulse over the step, the largest
  increment and the restitution target.

The coloured manifolds of a large world (``colouring.py``, ``lanes.py``): their
constraint columns ``con`` (CON_F, M) and lanes (LANE_F, M) float64, ``M`` the manifolds
the points can make, and their colouring's int arrays, kept as two flat arrays
(``colour_floats`` (CON_F + LANE_F, M), ``colour_ints``) that
``colouring.colour_arrays`` cuts only in a world that is coloured.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ._jit import cut, inline, kernel

MOVING, MOVABLE, STEP_INV_MASS, STEP_INV_MOMENT = 0, 1, 2, 3
ACCEL_X, ACCEL_Y, ACCEL_W, ROLL_H = 4, 5, 6, 7
SPEED, HALF_SPEC = 8, 9
X0, Y0, ANGLE0 = 10, 11, 12
LEFT, RIGHT, BOTTOM, TOP = 13, 14, 15, 16
REACH = 17  # SPEED plus what gravity, forces and springs can add within the step (m/s)
PUSHED = 18  # REACH plus what the bodies it may touch can add (m/s): its planes' margin
TERMS = 19
# The broadphase's boxes in its sweep order, field-major ``swept[field, p]`` for the p-th
# body swept (broadphase.sweep): its box, and 1.0 if it moves plus 2.0 if it is dynamic.
SWEPT_LEFT, SWEPT_RIGHT, SWEPT_BOTTOM, SWEPT_TOP, SWEPT_FLAGS = range(5)
SWEPT_F = 5
# The solver's body states ``states[i, field]`` in a coloured world (lanes.py): what its
# passes read and write of body i, in one cache line (Box2D's b2BodyState): velocity,
# motion since the step start, whether contacts move it (1.0).
SVX, SVY, SW, SDX, SDY, SDQ, SMOVABLE = range(7)
STATE_F = 8

# The columns a solver sweep reads come first, so a point's hot data spans three cache
# lines, not four.
NX, NY, SEP0 = 0, 1, 2  # normal (A to B) and separation at the step start (m)
RNA, RNB, RTA, RTB = 3, 4, 5, 6  # rA x n, rB x n, rA x t, rB x t
IMA, IMB, IIA, IIB = 7, 8, 9, 10  # step inverse masses and moments of A and B
NORMAL_MASS, TANGENT_MASS, MIXED_FRICTION = 11, 12, 13
BIAS_RATE, MASS_SCALE, IMPULSE_SCALE = 14, 15, 16  # the soft constraint
NORMAL_J, TANGENT_J = 17, 18  # accumulated impulses (N s)
STEP_J, MAX_J = 19, 20  # impulse over the step; largest solver increment (did it push?)
RAX, RAY, RBX, RBY = 21, 22, 23, 24  # anchors: offsets of the point from A's and B's centres
MIXED_RESTITUTION = 25
APPROACH_SPEED, NORMAL_ACCEL = 26, 27  # normal velocity and acceleration at the step start
SHARED = 28  # 1.0 if the point's pair has another point
TARGET = 29  # restitution: minus the normal velocity to reach
BOUNCE = 30  # restitution: 0.0 if the point does not bounce, else the next one's index + 1
KEEP = 31  # whose anchor follows its body: 0 A's, 1 B's, 2 two discs (see follow_bodies)
AGAINST_PLANE = 32  # how the sweeps take it: 1.0 B is a plane (solved last, solver.sweep),
IN_COLOUR = 2.0  # its manifold is coloured (colouring.py), 0.0 in the narrowphase's order
GROSS_J = 33  # sum of |normal| + |tangent| of every push over the step (N s)
DRIFT = 34  # a point that keeps its anchors: the farthest they moved apart this step (m)
POINT_F = 35
MERGED_F = 11  # = state.CONTACT_F: the contact cache being written

# Coloured manifolds (``colouring.py``, ``lanes.py``), field-major ``con[field, m]``: per
# manifold its normal, friction, step inverse masses and softness, then per point ``p``
# from ``POINT0 + p * PER_POINT`` its separation at the step start, Jacobian cross terms
# and masses, what the solver accumulates over the step and what ``follow_bodies`` reads
# and writes (the columns of the points of the same names: while the substeps run, a
# coloured point lives here).
COLOURS = 32  # colours a step (one bit each of an int64 mask a body)
CNX, CNY, CFRICTION, CIMA, CIMB, CIIA, CIIB, CBIAS_RATE, CMASS_SCALE, CIMPULSE_SCALE = range(10)
POINT0 = 10
PSEP0, PRNA, PRNB, PRTA, PRTB, PNORMAL_MASS, PTANGENT_MASS = range(7)
PNORMAL_J, PTANGENT_J, PSTEP_J, PMAX_J, PGROSS_J = range(7, 12)
PER_POINT = 12
# ... and per point from ``FOLLOW0 + p * PER_FOLLOW`` what only ``follow_bodies`` reads
# (after the columns the lane loop loads, which loads each of its columns in every lane)
FOLLOW0 = POINT0 + 2 * PER_POINT
PRAX, PRAY, PRBX, PRBY = range(4)  # the anchors as the narrowphase made them
PKEEP, PBOUNCES, PDRIFT = 4, 5, 6  # contacts.follow_bodies: KEEP, may it bounce?, DRIFT
PER_FOLLOW = 7
CON_F = FOLLOW0 + 2 * PER_FOLLOW
# Lanes ``lanes[field, m]``: body A's velocity (m/s, rad/s) and its position and rotation
# deltas since the step start (m, rad), then body B's.
LVAX, LVAY, LWA, LDXA, LDYA, LDQA, LVBX, LVBY, LWB, LDXB, LDYB, LDQB = range(12)
LANE_F = 12


@inline
def manifold_room(points: int) -> int:
    """How many two-point manifolds ``points`` points can make (with one to spare), as
    the length of a ``con`` and ``lanes`` row: rounded up to an odd number of 8-float
    cache lines.

    Why odd: a lane loop reads ~46 rows at one index ``m``, addresses a row length
    apart. Point capacities are powers of two, so an unpadded row is a power of two of
    bytes long and every one of those reads falls in the same set of the L1 and L2
    caches (their set is the address's bits 6-11 and 6-16): 46 lines in a 12- or 16-way
    set evict each other before the next lanes use them. A row of an odd number of lines
    puts row ``f``'s line in set ``f * odd mod sets``, a different set for each of them.
    Only where numbers lie changes, so no result does."""
    lines = (points // 2 + 1 + 7) // 8
    return 8 * (lines + 1 - lines % 2)


@inline
def colour_sizes(bodies: int, points: int) -> tuple[int, int]:
    """Lengths of the coloured manifolds' float and int scratch (``Scratch.colour_floats``,
    ``colour_ints``; ``colouring.colour_arrays`` cuts them)."""
    manifolds = manifold_room(points)  # 2 * manifolds >= points + 2: room for ``others``
    return (CON_F + LANE_F) * manifolds, 7 * manifolds + (COLOURS + 1) + bodies


def colour_scratch(bodies: int, points: int) -> tuple[np.ndarray, np.ndarray]:
    """A ``Scratch.colour_floats`` and ``colour_ints`` of their own, zeroed (for tests and
    benchmarks that colour captured points)."""
    ints = colour_sizes(bodies, points)[1]
    return np.zeros((CON_F + LANE_F, manifold_room(points))), np.zeros(ints, np.int64)


def row_sizes(bodies: int, points: int, pairs: int) -> tuple[int, int]:
    """Lengths of one float row and one int row."""
    colour_floats, colour_ints = colour_sizes(bodies, points)
    floats = bodies * (TERMS + SWEPT_F + STATE_F) + points * (POINT_F + MERGED_F) + colour_floats
    ints = 4 * pairs + (bodies + 1) + 6 * points + 3 * bodies + colour_ints
    return floats, ints


class Workspace:
    """Scratch rows for ``rows`` chunks of worlds (see the module docstring)."""

    def __init__(self, rows: int, bodies: int, points: int, pairs: int) -> None:
        self.rows, self.bodies, self.points, self.pairs = rows, bodies, points, pairs
        floats, ints = row_sizes(bodies, points, pairs)
        self.floats = np.zeros((rows, floats))
        self.ints = np.zeros((rows, ints), np.int64)

    def fits(self, rows: int, bodies: int, points: int, pairs: int) -> bool:
        return (
            rows <= self.rows
            and bodies == self.bodies
            and points <= self.points
            and pairs <= self.pairs
        )


class Scratch(NamedTuple):
    """One scratch row cut into its named arrays (``views``); numba passes it as a
    tuple, so a kernel reads ``scratch.points`` and nothing is copied."""

    terms: np.ndarray  # (N, TERMS) per-body step terms
    swept: np.ndarray  # (SWEPT_F, N) the broadphase's boxes in sweep order
    states: np.ndarray  # (N, STATE_F) the coloured passes' body states
    points: np.ndarray  # (C, POINT_F) this step's contact points
    merged: np.ndarray  # (C, MERGED_F) the contact cache being written
    point_ids: np.ndarray  # (C, 3) body A, body B, feature of each point
    merged_ids: np.ndarray  # (C, 3) the same for the cache being written
    pairs: np.ndarray  # (P, 2) candidate pairs from the broadphase
    sorted_pairs: np.ndarray  # (P, 2) room to sort them
    buckets: np.ndarray  # (N + 1,) the pairs' counting sort by first body
    parents: np.ndarray  # (N,) islands: union-find parents (sleep)
    members: np.ndarray  # (N,) islands: members in order (sleep)
    moving: np.ndarray  # (N,) the slots of the bodies that move this step, in slot order
    # The coloured manifolds' arrays, cut only where a world is coloured (cutting them
    # into their seven arrays at every call cost a small world 0.3 us a step):
    colour_floats: np.ndarray  # (CON_F + LANE_F, M) see colouring.colour_arrays
    colour_ints: np.ndarray  # (colour_sizes[1],)


@kernel
def views(floats: np.ndarray, ints: np.ndarray, bodies: int, points: int, pairs: int):
    """Cut one scratch row into its arrays (``Scratch``), each a borrowed view
    (``_jit.cut``: a call cuts them all, and slices and reshapes cost it more than its
    step's first stage)."""
    terms = cut(floats, 0, bodies, TERMS)
    at = bodies * TERMS
    swept = cut(floats, at, SWEPT_F, bodies)
    at += bodies * SWEPT_F
    states = cut(floats, at, bodies, STATE_F)
    at += bodies * STATE_F
    point_rows = cut(floats, at, points, POINT_F)
    at += points * POINT_F
    merged = cut(floats, at, points, MERGED_F)
    at += points * MERGED_F
    colour_floats, colour_ints = colour_sizes(bodies, points)
    coloured_floats = cut(floats, at, CON_F + LANE_F, colour_floats // (CON_F + LANE_F))
    pair_rows = cut(ints, 0, pairs, 2)
    at = 2 * pairs
    sorted_pairs = cut(ints, at, pairs, 2)
    at += 2 * pairs
    buckets = cut(ints, at, 1, bodies + 1)[0]
    at += bodies + 1
    point_ids = cut(ints, at, points, 3)
    at += 3 * points
    merged_ids = cut(ints, at, points, 3)
    at += 3 * points
    parents = cut(ints, at, 1, bodies)[0]
    at += bodies
    members = cut(ints, at, 1, bodies)[0]
    at += bodies
    moving = cut(ints, at, 1, bodies)[0]
    at += bodies
    coloured_ints = cut(ints, at, 1, colour_ints)[0]
    return Scratch(
        terms, swept, states, point_rows, merged, point_ids, merged_ids, pair_rows,
        sorted_pairs, buckets, parents, members, moving, coloured_floats, coloured_ints,
    )  # fmt: skip


def part_shapes(bodies: int, points: int, pairs: int) -> Scratch:
    """The arrays ``views`` cuts a row into, as separate ``((shape), dtype)`` each: the
    GPU keeps them apart (``core.gpu``), so each can lie world-innermost."""
    f8, i8 = np.float64, np.int64
    colour_ints = colour_sizes(bodies, points)[1]
    return Scratch(
        terms=((bodies, TERMS), f8),
        swept=((SWEPT_F, bodies), f8),
        states=((bodies, STATE_F), f8),
        points=((points, POINT_F), f8),
        merged=((points, MERGED_F), f8),
        point_ids=((points, 3), i8),
        merged_ids=((points, 3), i8),
        pairs=((pairs, 2), i8),
        sorted_pairs=((pairs, 2), i8),
        buckets=((bodies + 1,), i8),
        parents=((bodies,), i8),
        members=((bodies,), i8),
        moving=((bodies,), i8),
        colour_floats=((CON_F + LANE_F, manifold_room(points)), f8),
        colour_ints=((colour_ints,), i8),
    )


@inline
def scratch_row(parts, j):
    """Row ``j`` of every part (the GPU's scratch, ``part_shapes`` with a world axis in
    front): one world's ``Scratch``."""
    return Scratch(
        parts[0][j], parts[1][j], parts[2][j], parts[3][j], parts[4][j], parts[5][j],
        parts[6][j], parts[7][j], parts[8][j], parts[9][j], parts[10][j], parts[11][j],
        parts[12][j], parts[13][j], parts[14][j],
    )  # fmt: skip
