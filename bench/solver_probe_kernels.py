"""The kernels of ``bench/solver_probe.py``: one biased contact-solve pass over a compact
layout, in the narrowphase's order, coloured, and coloured in blocks of four lanes.

The layout (Box2D v3's, in numba arrays):

* body states ``states`` (N + 1, STATE_F): velocity, angular velocity and the position and
  rotation deltas since the step start, one 64-byte row in float64; row N is a dummy at
  rest that stands for every body that cannot move this step;
* manifold constraints ``con`` (CON_F, M), field-major: per two-point manifold its normal,
  friction, step inverse masses and softness, then per point the Jacobian's cross terms
  ``rA x n``, ``rB x n``, ``rA x t``, ``rB x t``, the separation at the step start, the
  normal and tangent masses and the accumulated impulses (a one-point manifold's second
  point has zero masses and solves to nothing);
* lanes ``lanes`` (LANE_F, M): a colour's two bodies' states gathered side by side.

Each manifold: both normals one after the other (Box2D v3's order, without impulse2d's
two-point block solve), then both frictions, within the cone. The soft normal row is
``lambda = -m (s_m v_n + bias) - s_i lambda_acc`` with ``bias = max(s_m rate C,
-push)`` for an overlap ``C < 0`` and ``C / h`` (arrive, no more) for a gap; see
``core.solver``.
"""

from __future__ import annotations

import numba
import numpy as np

from impulse2d.core.state import ANGLE, OMEGA, VX, VY, X, Y
from impulse2d.core.workspace import (
    ANGLE0,
    BIAS_RATE,
    IIA,
    IIB,
    IMA,
    IMB,
    IMPULSE_SCALE,
    MASS_SCALE,
    MAX_J,
    MIXED_FRICTION,
    NORMAL_J,
    NORMAL_MASS,
    NX,
    NY,
    RNA,
    RNB,
    RTA,
    RTB,
    SEP0,
    TANGENT_J,
    TANGENT_MASS,
    X0,
    Y0,
)

# body state columns (4 and 7 unused: a row is 8 wide)
SVX, SVY, SW, SDX, SDY, SDQ = 0, 1, 2, 4, 5, 6
STATE_F = 8
# manifold columns, then per point p at POINT0 + p * PER_POINT
CNX, CNY, CFRICTION, CIMA, CIMB, CIIA, CIIB, CBIAS_RATE, CMASS_SCALE, CIMPULSE_SCALE = range(10)
POINT0 = 10
PRNA, PRNB, PRTA, PRTB, PSEP0, PNM, PTM, PNJ, PTJ, PMAXJ = range(10)
PER_POINT = 10
CON_F = POINT0 + 2 * PER_POINT
# lane columns: body A's velocity and deltas, then body B's
LVAX, LVAY, LWA, LDXA, LDYA, LDQA, LVBX, LVBY, LWB, LDXB, LDYB, LDQB = range(12)
LANE_F = 12
# ``consts``: an array of the kernel's dtype, so float32 kernels never meet a float64 literal
# (numba would promote the arithmetic to float64)
INV_H, PUSH, ZERO, ONE = range(4)


@numba.njit(nogil=True, inline="always")
def _values(consts):
    """``consts`` as a tuple: values in registers, not loads that a store might alias."""
    return consts[INV_H], consts[PUSH], consts[ZERO], consts[ONE]


@numba.njit(nogil=True, inline="always")
def _soft_normal(acc, mass, s, vn, rate, soft_mass, soft_impulse, consts):
    """The new accumulated normal impulse of a point at separation ``s``. Both biases are
    computed before a plain select (a branch would split the block a vectoriser packs)."""
    inv_h, push, zero, one = consts[INV_H], consts[PUSH], consts[ZERO], consts[ONE]
    soft_bias = max(soft_mass * rate * s, -push)
    gap = s > zero
    mass_scale = one if gap else soft_mass
    impulse_scale = zero if gap else soft_impulse
    bias = s * inv_h if gap else soft_bias
    return max(acc - mass * (mass_scale * vn + bias) - impulse_scale * acc, zero)


@numba.njit(nogil=True, inline="always")
def _point_normal(con, m, p, v, consts):
    """Point ``p``'s normal solve: ``(v updated, new impulse, new largest increment)``."""
    vax, vay, wa, dxa, dya, dqa, vbx, vby, wb, dxb, dyb, dqb = v
    base = POINT0 + p * PER_POINT
    nx, ny = con[CNX, m], con[CNY, m]
    rna, rnb = con[base + PRNA, m], con[base + PRNB, m]
    s = con[base + PSEP0, m] + nx * (dxb - dxa) + ny * (dyb - dya) + rnb * dqb - rna * dqa
    vn = nx * (vbx - vax) + ny * (vby - vay) + rnb * wb - rna * wa
    acc = con[base + PNJ, m]
    new = _soft_normal(acc, con[base + PNM, m], s, vn, con[CBIAS_RATE, m], con[CMASS_SCALE, m],
                       con[CIMPULSE_SCALE, m], consts)  # fmt: skip
    d = new - acc
    ima, imb, iia, iib = con[CIMA, m], con[CIMB, m], con[CIIA, m], con[CIIB, m]
    v = (vax - ima * d * nx, vay - ima * d * ny, wa - iia * rna * d, dxa, dya, dqa,
         vbx + imb * d * nx, vby + imb * d * ny, wb + iib * rnb * d, dxb, dyb, dqb)  # fmt: skip
    return v, new, max(con[base + PMAXJ, m], d)


@numba.njit(nogil=True, inline="always")
def _point_friction(con, m, p, v, normal):
    """Point ``p``'s friction within ``friction * normal``: ``(v updated, new impulse)``."""
    vax, vay, wa, dxa, dya, dqa, vbx, vby, wb, dxb, dyb, dqb = v
    base = POINT0 + p * PER_POINT
    nx, ny = con[CNX, m], con[CNY, m]
    rta, rtb = con[base + PRTA, m], con[base + PRTB, m]
    vt = ny * (vbx - vax) - nx * (vby - vay) + rtb * wb - rta * wa  # t = (n_y, -n_x)
    limit = con[CFRICTION, m] * normal
    old = con[base + PTJ, m]
    new = min(max(old - con[base + PTM, m] * vt, -limit), limit)
    d = new - old
    ima, imb, iia, iib = con[CIMA, m], con[CIMB, m], con[CIIA, m], con[CIIB, m]
    v = (vax - ima * d * ny, vay + ima * d * nx, wa - iia * rta * d, dxa, dya, dqa,
         vbx + imb * d * ny, vby - imb * d * nx, wb + iib * rtb * d, dxb, dyb, dqb)  # fmt: skip
    return v, new


@numba.njit(nogil=True, inline="always")
def manifold(con, m, v, consts):
    """Manifold ``m`` solved from the 12 lane values ``v`` as a pure function of what it
    loads: ``(v, impulses)``, the impulses ``(normal, largest, friction)`` of each point.
    Nothing is stored here, so a block of lanes can load everything before it stores."""
    v, n0, max0 = _point_normal(con, m, 0, v, consts)
    v, n1, max1 = _point_normal(con, m, 1, v, consts)
    v, t0 = _point_friction(con, m, 0, v, n0)
    v, t1 = _point_friction(con, m, 1, v, n1)
    return v, (n0, max0, t0, n1, max1, t1)


@numba.njit(nogil=True, inline="always")
def _store_impulses(con, m, impulses):
    for p in range(2):
        base = POINT0 + p * PER_POINT
        con[base + PNJ, m] = impulses[3 * p]
        con[base + PMAXJ, m] = impulses[3 * p + 1]
        con[base + PTJ, m] = impulses[3 * p + 2]


@numba.njit(nogil=True, inline="always")
def _state(states, a, b):
    return (states[a, SVX], states[a, SVY], states[a, SW], states[a, SDX], states[a, SDY],
            states[a, SDQ], states[b, SVX], states[b, SVY], states[b, SW], states[b, SDX],
            states[b, SDY], states[b, SDQ])  # fmt: skip


@numba.njit(nogil=True)
def compact(states, con, pair, consts, passes):
    """Gauss-Seidel in the narrowphase's order, the body states read and written in place."""
    consts = _values(consts)
    dummy = states.shape[0] - 1
    for _ in range(passes):
        for m in range(pair.shape[0]):
            a, b = pair[m, 0], pair[m, 1]
            v, impulses = manifold(con, m, _state(states, a, b), consts)
            _store_impulses(con, m, impulses)
            if a != dummy:
                states[a, SVX], states[a, SVY], states[a, SW] = v[0], v[1], v[2]
            if b != dummy:
                states[b, SVX], states[b, SVY], states[b, SW] = v[6], v[7], v[8]


@numba.njit(nogil=True)
def gather(states, pair, lanes, start, end):
    """The two bodies' states of manifolds ``start:end`` into their lanes."""
    for m in range(start, end):
        v = _state(states, pair[m, 0], pair[m, 1])
        for f in range(LANE_F):
            lanes[f, m] = v[f]


@numba.njit(nogil=True)
def scatter(states, pair, lanes, start, end):
    """The lanes' velocities back to the moving bodies (a colour holds each once)."""
    dummy = states.shape[0] - 1
    for m in range(start, end):
        a, b = pair[m, 0], pair[m, 1]
        for f in range(3):
            if a != dummy:
                states[a, SVX + f] = lanes[LVAX + f, m]
            if b != dummy:
                states[b, SVX + f] = lanes[LVBX + f, m]


@numba.njit(nogil=True, inline="always")
def _lane_values(lanes, m):
    a = (lanes[0, m], lanes[1, m], lanes[2, m], lanes[3, m], lanes[4, m], lanes[5, m])
    b = (lanes[6, m], lanes[7, m], lanes[8, m], lanes[9, m], lanes[10, m], lanes[11, m])
    return a + b


@numba.njit(nogil=True, inline="always")
def _store_lane(con, lanes, m, solved):
    v, impulses = solved
    for f in range(3):
        lanes[LVAX + f, m] = v[f]
        lanes[LVBX + f, m] = v[6 + f]
    _store_impulses(con, m, impulses)


@numba.njit(nogil=True)
def solve_lanes(con, lanes, start, end, consts):
    """One colour's lanes, one after the other (they share no moving body)."""
    consts = _values(consts)
    for m in range(start, end):
        _store_lane(con, lanes, m, manifold(con, m, _lane_values(lanes, m), consts))


@numba.njit(nogil=True)
def solve_blocks(con, lanes, start, end, consts):
    """Blocks of four lanes (a colour padded to a multiple of four): the four lanes' loads
    and arithmetic, then their stores, the straight-line code LLVM's SLP vectoriser packs
    when numba enables it (``NUMBA_SLP_VECTORIZE=1``; numba's default is off)."""
    consts = _values(consts)
    for m in range(start, end, 4):
        s0 = manifold(con, m, _lane_values(lanes, m), consts)
        s1 = manifold(con, m + 1, _lane_values(lanes, m + 1), consts)
        s2 = manifold(con, m + 2, _lane_values(lanes, m + 2), consts)
        s3 = manifold(con, m + 3, _lane_values(lanes, m + 3), consts)
        _store_lane(con, lanes, m, s0)
        _store_lane(con, lanes, m + 1, s1)
        _store_lane(con, lanes, m + 2, s2)
        _store_lane(con, lanes, m + 3, s3)


@numba.njit(nogil=True)
def coloured(states, con, pair, starts, lanes, consts, passes, blocks):
    """Colour after colour (``starts``: each colour's first manifold): gather, solve the
    lanes (``blocks``: in blocks of four), scatter."""
    for _ in range(passes):
        for c in range(starts.shape[0] - 1):
            start, end = starts[c], starts[c + 1]
            gather(states, pair, lanes, start, end)
            if blocks:
                solve_blocks(con, lanes, start, end, consts)
            else:
                solve_lanes(con, lanes, start, end, consts)
            scatter(states, pair, lanes, start, end)


@numba.njit(nogil=True)
def normals_only(va, vb, acc, mass, sep, consts, passes):
    """The arithmetic floor: one point's soft normal impulse a lane, each field an array of
    its own, the velocities already gathered, no friction, gather or scatter. numba/LLVM
    vectorises this loop (``NUMBA_LOOP_VECTORIZE=0`` gives the same loop scalar)."""
    consts = _values(consts)
    for _ in range(passes):
        for i in range(acc.shape[0]):
            s = sep[i]
            soft_bias = max(s / consts[INV_H], -consts[PUSH])
            bias = s * consts[INV_H] if s > consts[ZERO] else soft_bias
            old = acc[i]
            new = max(old - mass[i] * (vb[i] - va[i] + bias), consts[ZERO])
            acc[i] = new
            va[i] -= new - old
            vb[i] += new - old


# -- building the layout from a step's points ------------------------------------------------
def manifolds(cap: dict) -> tuple[np.ndarray, np.ndarray]:
    """The points grouped into two-point manifolds: ``(con (CON_F, M), bodies (M, 2))``;
    a one-point manifold's second point has zero masses, so it solves to nothing. A body
    that cannot move is the dummy state row ``N`` (always at rest)."""
    points, ids, movable = cap["points"], cap["ids"], cap["movable"]
    dummy = cap["body"].shape[1]
    groups: list[list[int]] = []
    for k in range(cap["n"]):
        same = groups and ids[groups[-1][0], 0] == ids[k, 0] and ids[groups[-1][0], 1] == ids[k, 1]
        if same and len(groups[-1]) < 2:
            groups[-1].append(k)
        else:
            groups.append([k])
    con = np.zeros((CON_F, len(groups)))
    pair = np.zeros((len(groups), 2), np.int64)
    for m, group in enumerate(groups):
        first = points[group[0]]
        a, b = ids[group[0], 0], ids[group[0], 1]
        pair[m] = (a if movable[a] else dummy, b if movable[b] else dummy)
        for col, src in ((CNX, NX), (CNY, NY), (CFRICTION, MIXED_FRICTION), (CIMA, IMA),
                         (CIMB, IMB), (CIIA, IIA), (CIIB, IIB), (CBIAS_RATE, BIAS_RATE),
                         (CMASS_SCALE, MASS_SCALE), (CIMPULSE_SCALE, IMPULSE_SCALE)):  # fmt: skip
            con[col, m] = first[src]
        for p, k in enumerate(group):
            base = POINT0 + p * PER_POINT
            for col, src in ((PRNA, RNA), (PRNB, RNB), (PRTA, RTA), (PRTB, RTB), (PSEP0, SEP0),
                             (PNM, NORMAL_MASS), (PTM, TANGENT_MASS), (PNJ, NORMAL_J),
                             (PTJ, TANGENT_J), (PMAXJ, MAX_J)):  # fmt: skip
                con[base + col, m] = points[k, src]
    return con, pair


def colour(pair: np.ndarray, dummy: int) -> np.ndarray:
    """Greedy colouring: each manifold takes the first colour neither of its moving bodies
    has yet (at most 64; the dummy, a body at rest, may be in every manifold of a colour)."""
    used = np.zeros(dummy + 1, np.uint64)
    colours = np.zeros(pair.shape[0], np.int64)
    for m, (a, b) in enumerate(pair):
        taken = int(used[a] if a != dummy else 0) | int(used[b] if b != dummy else 0)
        c = 0
        while taken >> c & 1:
            c += 1
        if c >= 64:
            raise RuntimeError("more than 64 colours")
        colours[m] = c
        for body in (a, b):
            if body != dummy:
                used[body] = np.uint64(int(used[body]) | 1 << c)
    return colours


def body_states(cap: dict, dtype) -> np.ndarray:
    """The compact body states (N + 1, STATE_F), the dummy last."""
    body, terms = cap["body"][0], cap["terms"]
    states = np.zeros((body.shape[0] + 1, STATE_F), dtype)
    states[:-1, SVX], states[:-1, SVY], states[:-1, SW] = body[:, VX], body[:, VY], body[:, OMEGA]
    states[:-1, SDX] = body[:, X] - terms[:, X0]
    states[:-1, SDY] = body[:, Y] - terms[:, Y0]
    states[:-1, SDQ] = body[:, ANGLE] - terms[:, ANGLE0]
    movable = np.append(cap["movable"], False)
    states[~movable] = 0.0
    return states


def pad_colours(con, pair, starts, width, dummy):
    """Each colour padded with empty manifolds (zero masses, both bodies the dummy) to a
    multiple of ``width`` lanes, as Box2D pads its SIMD constraints."""
    cons, pairs, new_starts = [], [], [0]
    for c in range(starts.size - 1):
        size = starts[c + 1] - starts[c]
        pad = -size % width
        cons += [con[:, starts[c] : starts[c + 1]], np.zeros((con.shape[0], pad))]
        pairs += [pair[starts[c] : starts[c + 1]], np.full((pad, 2), dummy, np.int64)]
        new_starts.append(new_starts[-1] + size + pad)
    padded = np.ascontiguousarray(np.concatenate(cons, axis=1))
    return padded, np.concatenate(pairs), np.array(new_starts, np.int64)


def ground_share(con, pair, dummy, weight_impulse) -> float:
    """The normal impulse on the ground (body A the dummy) over ``m g h``."""
    ground = pair[:, 0] == dummy
    total = con[POINT0 + PNJ][ground].sum() + con[POINT0 + PER_POINT + PNJ][ground].sum()
    return float(total) / weight_impulse
