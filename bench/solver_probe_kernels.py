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

import llvmlite.binding
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

# LLVM's loop vectoriser gives up on a loop that needs more run-time alias checks than
# these limits (8 by default): ``solve_vector`` needs dozens. Process-wide LLVM options;
# they only let more loops vectorise, which changes no result (no fast-math).
for _option in ("-runtime-memory-check-threshold=512", "-vectorize-memory-check-threshold=4096",
                "-memory-check-merge-threshold=4096"):  # fmt: skip
    llvmlite.binding.set_option("", _option)

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
def _row(c, p, v):
    """Point ``p``'s separation now (``C`` at the step start plus ``J . dq``) and its
    normal relative velocity ``J . V``."""
    vax, vay, wa, dxa, dya, dqa, vbx, vby, wb, dxb, dyb, dqb = v
    base = POINT0 + p * PER_POINT
    nx, ny, rna, rnb = c[CNX], c[CNY], c[base + PRNA], c[base + PRNB]
    s = c[base + PSEP0] + nx * (dxb - dxa) + ny * (dyb - dya) + rnb * dqb - rna * dqa
    return s, nx * (vbx - vax) + ny * (vby - vay) + rnb * wb - rna * wa


@numba.njit(nogil=True, inline="always")
def _push_normal(c, p, v, d):
    """``v`` after an impulse ``d`` along the normal at point ``p`` (on B; minus on A)."""
    vax, vay, wa, dxa, dya, dqa, vbx, vby, wb, dxb, dyb, dqb = v
    base = POINT0 + p * PER_POINT
    nx, ny, rna, rnb = c[CNX], c[CNY], c[base + PRNA], c[base + PRNB]
    ima, imb, iia, iib = c[CIMA], c[CIMB], c[CIIA], c[CIIB]
    return (vax - ima * d * nx, vay - ima * d * ny, wa - iia * rna * d, dxa, dya, dqa,
            vbx + imb * d * nx, vby + imb * d * ny, wb + iib * rnb * d, dxb, dyb, dqb)  # fmt: skip


@numba.njit(nogil=True, inline="always")
def _point_normal(c, p, v, consts):
    """Point ``p``'s normal solve: ``(v updated, new impulse, new largest increment)``."""
    s, vn = _row(c, p, v)
    base = POINT0 + p * PER_POINT
    acc = c[base + PNJ]
    new = _soft_normal(acc, c[base + PNM], s, vn, c[CBIAS_RATE], c[CMASS_SCALE],
                       c[CIMPULSE_SCALE], consts)  # fmt: skip
    return _push_normal(c, p, v, new - acc), new, max(c[base + PMAXJ], new - acc)


@numba.njit(nogil=True, inline="always")
def _soft_coefficients(c, s, inv_h, push):
    """``(mass_scale, bias, impulse_scale)`` of a point at separation ``s``."""
    if s > 0.0:
        return 1.0, s * inv_h, 0.0
    mass_scale = c[CMASS_SCALE]
    return mass_scale, max(mass_scale * c[CBIAS_RATE] * s, -push), c[CIMPULSE_SCALE]


@numba.njit(nogil=True, inline="always")
def _block_increments(c, v, consts):
    """Both normal increments of a two-point manifold at once, as ``core.solver``'s
    ``solve_pair_normals`` finds them (the 2x2 complementarity problem of the soft rows,
    its four cases tried in order): ``(found, d0, d1)``. float64 only."""
    ima, imb, iia, iib = c[CIMA], c[CIMB], c[CIIA], c[CIIB]
    b0, b1 = POINT0, POINT0 + PER_POINT
    rna0, rnb0, rna1, rnb1 = c[b0 + PRNA], c[b0 + PRNB], c[b1 + PRNA], c[b1 + PRNB]
    k11 = ima + imb + iia * rna0 * rna0 + iib * rnb0 * rnb0
    k22 = ima + imb + iia * rna1 * rna1 + iib * rnb1 * rnb1
    k12 = ima + imb + iia * rna0 * rna1 + iib * rnb0 * rnb1
    if not k11 * k22 - k12 * k12 > 1e-3 * k11 * k22:
        return False, 0.0, 0.0
    (s0, vn0), (s1, vn1) = _row(c, 0, v), _row(c, 1, v)
    ms0, bias0, is0 = _soft_coefficients(c, s0, consts[INV_H], consts[PUSH])
    ms1, bias1, is1 = _soft_coefficients(c, s1, consts[INV_H], consts[PUSH])
    acc0, acc1 = c[b0 + PNJ], c[b1 + PNJ]
    a11, a12, r1 = ms0 * k11 + is0 * k11, ms0 * k12, -(ms0 * vn0 + bias0 + is0 * k11 * acc0)
    a21, a22, r2 = ms1 * k12, ms1 * k22 + is1 * k22, -(ms1 * vn1 + bias1 + is1 * k22 * acc1)
    det = a11 * a22 - a12 * a21
    if det != 0.0:  # both push
        d0, d1 = (r1 * a22 - a12 * r2) / det, (a11 * r2 - a21 * r1) / det
        if acc0 + d0 >= 0.0 and acc1 + d1 >= 0.0:
            return True, d0, d1
    d1 = -acc1  # only the first pushes
    d0 = (r1 - a12 * d1) / a11
    if acc0 + d0 >= 0.0 and a21 * d0 + a22 * d1 - r2 >= 0.0:
        return True, d0, d1
    d0 = -acc0  # only the second
    d1 = (r2 - a21 * d0) / a22
    if acc1 + d1 >= 0.0 and a11 * d0 + a12 * d1 - r1 >= 0.0:
        return True, d0, d1
    d0, d1 = -acc0, -acc1  # neither
    return a11 * d0 + a12 * d1 - r1 >= 0.0 and a21 * d0 + a22 * d1 - r2 >= 0.0, d0, d1


@numba.njit(nogil=True, inline="always")
def _block_normals(c, v, consts):
    """Both normals together, or one after the other where the block has no solution:
    ``(v, n0, max0, n1, max1)``."""
    found, d0, d1 = _block_increments(c, v, consts)
    if not found:
        v, n0, max0 = _point_normal(c, 0, v, consts)
        v, n1, max1 = _point_normal(c, 1, v, consts)
        return v, n0, max0, n1, max1
    b0, b1 = POINT0, POINT0 + PER_POINT
    v = _push_normal(c, 1, _push_normal(c, 0, v, d0), d1)
    n0, n1 = c[b0 + PNJ] + d0, c[b1 + PNJ] + d1
    return v, n0, max(c[b0 + PMAXJ], d0), n1, max(c[b1 + PMAXJ], d1)


@numba.njit(nogil=True, inline="always")
def _point_friction(c, p, v, normal):
    """Point ``p``'s friction within ``friction * normal``: ``(v updated, new impulse)``."""
    vax, vay, wa, dxa, dya, dqa, vbx, vby, wb, dxb, dyb, dqb = v
    base = POINT0 + p * PER_POINT
    nx, ny = c[CNX], c[CNY]
    rta, rtb = c[base + PRTA], c[base + PRTB]
    vt = ny * (vbx - vax) - nx * (vby - vay) + rtb * wb - rta * wa  # t = (n_y, -n_x)
    limit = c[CFRICTION] * normal
    old = c[base + PTJ]
    new = min(max(old - c[base + PTM] * vt, -limit), limit)
    d = new - old
    ima, imb, iia, iib = c[CIMA], c[CIMB], c[CIIA], c[CIIB]
    v = (vax - ima * d * ny, vay + ima * d * nx, wa - iia * rta * d, dxa, dya, dqa,
         vbx + imb * d * ny, vby - imb * d * nx, wb + iib * rtb * d, dxb, dyb, dqb)  # fmt: skip
    return v, new


@numba.njit(nogil=True, inline="always")
def manifold(c, v, consts):
    """A manifold solved from its constraint values ``c`` (CON_F) and the 12 lane values
    ``v``, a pure function of values: ``(v, impulses)``, the impulses ``(normal, largest,
    friction)`` of each point. Nothing is loaded or stored here, so a block of lanes can
    load everything before it stores, and a lane loop holds no call that takes an array."""
    v, n0, max0 = _point_normal(c, 0, v, consts)
    v, n1, max1 = _point_normal(c, 1, v, consts)
    v, t0 = _point_friction(c, 0, v, n0)
    v, t1 = _point_friction(c, 1, v, n1)
    return v, (n0, max0, t0, n1, max1, t1)


@numba.njit(nogil=True, inline="always")
def manifold_block(c, v, consts):
    """``manifold`` with the two normals solved together (``_block_normals``)."""
    v, n0, max0, n1, max1 = _block_normals(c, v, consts)
    v, t0 = _point_friction(c, 0, v, n0)
    v, t1 = _point_friction(c, 1, v, n1)
    return v, (n0, max0, t0, n1, max1, t1)


@numba.njit(nogil=True, inline="always")
def _block_select(c, v, consts):
    """``_block_increments`` without branches: every case computed, the first that holds
    selected (the loop vectoriser turns selects into blends, not branches). Lanes whose
    cases divide by zero (the padding, a degenerate block) select nothing from them."""
    ima, imb, iia, iib = c[CIMA], c[CIMB], c[CIIA], c[CIIB]
    b0, b1 = POINT0, POINT0 + PER_POINT
    rna0, rnb0, rna1, rnb1 = c[b0 + PRNA], c[b0 + PRNB], c[b1 + PRNA], c[b1 + PRNB]
    k11 = ima + imb + iia * rna0 * rna0 + iib * rnb0 * rnb0
    k22 = ima + imb + iia * rna1 * rna1 + iib * rnb1 * rnb1
    k12 = ima + imb + iia * rna0 * rna1 + iib * rnb0 * rnb1
    solvable = k11 * k22 - k12 * k12 > 1e-3 * k11 * k22
    (s0, vn0), (s1, vn1) = _row(c, 0, v), _row(c, 1, v)
    ms0, bias0, is0 = _soft_select(c, s0, consts)
    ms1, bias1, is1 = _soft_select(c, s1, consts)
    acc0, acc1 = c[b0 + PNJ], c[b1 + PNJ]
    a11, a12, r1 = ms0 * k11 + is0 * k11, ms0 * k12, -(ms0 * vn0 + bias0 + is0 * k11 * acc0)
    a21, a22, r2 = ms1 * k12, ms1 * k22 + is1 * k22, -(ms1 * vn1 + bias1 + is1 * k22 * acc1)
    det = a11 * a22 - a12 * a21
    safe_det = det if det != 0.0 else 1.0
    both0, both1 = (r1 * a22 - a12 * r2) / safe_det, (a11 * r2 - a21 * r1) / safe_det
    ok_both = det != 0.0 and acc0 + both0 >= 0.0 and acc1 + both1 >= 0.0
    first0 = (r1 + a12 * acc1) / (a11 if a11 != 0.0 else 1.0)
    ok_first = acc0 + first0 >= 0.0 and a21 * first0 - a22 * acc1 - r2 >= 0.0
    second1 = (r2 + a21 * acc0) / (a22 if a22 != 0.0 else 1.0)
    ok_second = acc1 + second1 >= 0.0 and -a11 * acc0 + a12 * second1 - r1 >= 0.0
    ok_neither = -a11 * acc0 - a12 * acc1 - r1 >= 0.0 and -a21 * acc0 - a22 * acc1 - r2 >= 0.0
    d0 = both0 if ok_both else (first0 if ok_first else -acc0)
    d1 = both1 if ok_both else (-acc1 if ok_first else (second1 if ok_second else -acc1))
    found = solvable and (ok_both or ok_first or ok_second or ok_neither)
    return found, d0, d1


@numba.njit(nogil=True, inline="always")
def _soft_select(c, s, consts):
    """``_soft_coefficients`` by selects."""
    gap = s > 0.0
    mass_scale = c[CMASS_SCALE]
    soft_bias = max(mass_scale * c[CBIAS_RATE] * s, -consts[PUSH])
    return (1.0 if gap else mass_scale, s * consts[INV_H] if gap else soft_bias,
            0.0 if gap else c[CIMPULSE_SCALE])  # fmt: skip


@numba.njit(nogil=True, inline="always")
def manifold_block_select(c, v, consts):
    """``manifold_block`` by selects: the block and the one-after-the-other solves both
    computed, the block's taken where it holds (float64 only)."""
    found, d0, d1 = _block_select(c, v, consts)
    v_seq, n0, max0 = _point_normal(c, 0, v, consts)
    v_seq, n1, max1 = _point_normal(c, 1, v_seq, consts)
    v_block = _push_normal(c, 1, _push_normal(c, 0, v, d0), d1)
    b0, b1 = POINT0, POINT0 + PER_POINT
    n0 = c[b0 + PNJ] + d0 if found else n0
    n1 = c[b1 + PNJ] + d1 if found else n1
    max0 = max(c[b0 + PMAXJ], d0) if found else max0
    max1 = max(c[b1 + PMAXJ], d1) if found else max1
    v = (v_block[0] if found else v_seq[0], v_block[1] if found else v_seq[1],
         v_block[2] if found else v_seq[2], v[3], v[4], v[5],
         v_block[6] if found else v_seq[6], v_block[7] if found else v_seq[7],
         v_block[8] if found else v_seq[8], v[9], v[10], v[11])  # fmt: skip
    v, t0 = _point_friction(c, 0, v, n0)
    v, t1 = _point_friction(c, 1, v, n1)
    return v, (n0, max0, t0, n1, max1, t1)


@numba.njit(nogil=True, inline="always")
def _con_values(con, m):
    a = (con[0, m], con[1, m], con[2, m], con[3, m], con[4, m], con[5, m], con[6, m])
    b = (con[7, m], con[8, m], con[9, m], con[10, m], con[11, m], con[12, m], con[13, m])
    d = (con[14, m], con[15, m], con[16, m], con[17, m], con[18, m], con[19, m], con[20, m])
    e = (con[21, m], con[22, m], con[23, m], con[24, m], con[25, m], con[26, m], con[27, m])
    return a + b + d + e + (con[28, m], con[29, m])


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


@numba.njit(nogil=True, inline="always")
def _compact(states, con, pair, consts, passes, solve):
    dummy = states.shape[0] - 1
    consts = _values(consts)
    for _ in range(passes):
        for m in range(pair.shape[0]):
            a, b = pair[m, 0], pair[m, 1]
            v, impulses = solve(_con_values(con, m), _state(states, a, b), consts)
            _store_impulses(con, m, impulses)
            if a != dummy:
                states[a, SVX], states[a, SVY], states[a, SW] = v[0], v[1], v[2]
            if b != dummy:
                states[b, SVX], states[b, SVY], states[b, SW] = v[6], v[7], v[8]


@numba.njit(nogil=True)
def compact(states, con, pair, consts, passes):
    """Gauss-Seidel in the narrowphase's order, the body states read and written in place."""
    _compact(states, con, pair, consts, passes, manifold)


@numba.njit(nogil=True)
def compact_block(states, con, pair, consts, passes):
    """``compact`` with each manifold's two normals solved together (float64 only)."""
    _compact(states, con, pair, consts, passes, manifold_block)


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


@numba.njit(nogil=True, inline="always")
def _solve_lanes(con, lanes, start, end, consts, solve):
    consts = _values(consts)
    for m in range(start, end):
        _store_lane(con, lanes, m, solve(_con_values(con, m), _lane_values(lanes, m), consts))


@numba.njit(nogil=True)
def solve_lanes(con, lanes, start, end, consts):
    """One colour's lanes, one after the other (they share no moving body)."""
    _solve_lanes(con, lanes, start, end, consts, manifold)


@numba.njit(nogil=True)
def solve_lanes_block(con, lanes, start, end, consts):
    """``solve_lanes`` with the block solve chosen by selects (``manifold_block_select``)."""
    _solve_lanes(con, lanes, start, end, consts, manifold_block_select)


@numba.njit(nogil=True)
def solve_blocks(con, lanes, start, end, consts):
    """Blocks of four lanes (a colour padded to a multiple of four): the four lanes' loads
    and arithmetic, then their stores, the straight-line code LLVM's SLP vectoriser packs
    when numba enables it (``NUMBA_SLP_VECTORIZE=1``; numba's default is off)."""
    consts = _values(consts)
    for m in range(start, end, 4):
        s0 = manifold(_con_values(con, m), _lane_values(lanes, m), consts)
        s1 = manifold(_con_values(con, m + 1), _lane_values(lanes, m + 1), consts)
        s2 = manifold(_con_values(con, m + 2), _lane_values(lanes, m + 2), consts)
        s3 = manifold(_con_values(con, m + 3), _lane_values(lanes, m + 3), consts)
        _store_lane(con, lanes, m, s0)
        _store_lane(con, lanes, m + 1, s1)
        _store_lane(con, lanes, m + 2, s2)
        _store_lane(con, lanes, m + 3, s3)


@numba.njit(nogil=True, inline="always")
def _solve_vector(con, lanes, start, end, consts, solve):
    """A colour's lanes in the form LLVM's loop vectoriser takes: every load and store
    written in the loop itself (an inlined helper that takes an array leaves numba's
    reference-count calls in the loop when the vectoriser runs), the index unsigned (no
    negative-index wrap-around), and the run-time alias checks allowed by the LLVM
    options set above (each pair of a stored row and another row of the same array needs
    one: their distance is a run-time shape). Lane arithmetic is IEEE elementwise, so the
    vectorised loop is bitwise the scalar one."""
    consts = _values(consts)
    for m in range(np.uint64(start), np.uint64(end)):
        a = (lanes[0, m], lanes[1, m], lanes[2, m], lanes[3, m], lanes[4, m], lanes[5, m])
        b = (lanes[6, m], lanes[7, m], lanes[8, m], lanes[9, m], lanes[10, m], lanes[11, m])
        c0 = (con[0, m], con[1, m], con[2, m], con[3, m], con[4, m], con[5, m], con[6, m])
        c1 = (con[7, m], con[8, m], con[9, m], con[10, m], con[11, m], con[12, m], con[13, m])
        c2 = (con[14, m], con[15, m], con[16, m], con[17, m], con[18, m], con[19, m], con[20, m])
        c3 = (con[21, m], con[22, m], con[23, m], con[24, m], con[25, m], con[26, m], con[27, m])
        v, j = solve(c0 + c1 + c2 + c3 + (con[28, m], con[29, m]), a + b, consts)
        lanes[LVAX, m], lanes[LVAY, m], lanes[LWA, m] = v[0], v[1], v[2]
        lanes[LVBX, m], lanes[LVBY, m], lanes[LWB, m] = v[6], v[7], v[8]
        con[POINT0 + PNJ, m], con[POINT0 + PMAXJ, m], con[POINT0 + PTJ, m] = j[0], j[1], j[2]
        second = POINT0 + PER_POINT
        con[second + PNJ, m], con[second + PMAXJ, m], con[second + PTJ, m] = j[3], j[4], j[5]


@numba.njit(nogil=True)
def solve_vector(con, lanes, start, end, consts):
    """``solve_lanes`` vectorised (``_solve_vector``)."""
    _solve_vector(con, lanes, start, end, consts, manifold)


@numba.njit(nogil=True)
def solve_vector_block(con, lanes, start, end, consts):
    """``solve_lanes_block`` vectorised (float64 only)."""
    _solve_vector(con, lanes, start, end, consts, manifold_block_select)


# How each colour's lanes are solved (``coloured``'s ``how``).
LANE_BY_LANE, BLOCKS_OF_FOUR, VECTOR = 0, 1, 2


@numba.njit(nogil=True)
def coloured(states, con, pair, starts, lanes, consts, passes, how):
    """Colour after colour (``starts``: each colour's first manifold): gather, solve the
    lanes (``how``), scatter."""
    for _ in range(passes):
        for c in range(starts.shape[0] - 1):
            start, end = starts[c], starts[c + 1]
            gather(states, pair, lanes, start, end)
            if how == BLOCKS_OF_FOUR:
                solve_blocks(con, lanes, start, end, consts)
            elif how == VECTOR:
                solve_vector(con, lanes, start, end, consts)
            else:
                solve_lanes(con, lanes, start, end, consts)
            scatter(states, pair, lanes, start, end)


@numba.njit(nogil=True)
def coloured_block(states, con, pair, starts, lanes, consts, passes, vector):
    """``coloured`` with the block solve by selects, lane by lane or vectorised (float64)."""
    for _ in range(passes):
        for c in range(starts.shape[0] - 1):
            start, end = starts[c], starts[c + 1]
            gather(states, pair, lanes, start, end)
            if vector:
                solve_vector_block(con, lanes, start, end, consts)
            else:
                solve_lanes_block(con, lanes, start, end, consts)
            scatter(states, pair, lanes, start, end)


@numba.njit(nogil=True)
def colour_manifolds(pair, dummy, colours):
    """Greedy colouring: each manifold takes the first colour neither of its moving bodies
    has yet, a 64-bit mask a body; the dummy (every body that cannot move) may be in every
    manifold of a colour. Returns the number of colours, or -1 past 64."""
    used = np.zeros(dummy + 1, np.uint64)
    count = 0
    for m in range(pair.shape[0]):
        a, b = pair[m, 0], pair[m, 1]
        taken = (used[a] if a != dummy else np.uint64(0)) | (
            used[b] if b != dummy else np.uint64(0)
        )
        c = 0
        while c < 64 and (taken >> np.uint64(c)) & np.uint64(1):
            c += 1
        if c == 64:
            return -1
        colours[m] = c
        bit = np.uint64(1) << np.uint64(c)
        used[a] |= bit
        used[b] |= bit
        count = max(count, c + 1)
    return count


@numba.njit(nogil=True)
def colour_and_sort(con, pair, dummy, colours, sorted_con, sorted_pair, starts):
    """What colouring costs a step: colour the manifolds, then a counting sort of their
    constraint columns and body pairs into colour order (``starts``: each colour's first);
    returns the number of colours."""
    count = colour_manifolds(pair, dummy, colours)
    starts[:] = 0
    for m in range(pair.shape[0]):
        starts[colours[m] + 1] += 1
    for c in range(count):
        starts[c + 1] += starts[c]
    fill = starts[:count].copy()
    for m in range(pair.shape[0]):
        k = fill[colours[m]]
        fill[colours[m]] += 1
        sorted_pair[k, 0], sorted_pair[k, 1] = pair[m, 0], pair[m, 1]
        for f in range(con.shape[0]):
            sorted_con[f, k] = con[f, m]
    return count


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
    """The colour of each manifold (``colour_manifolds``)."""
    colours = np.zeros(pair.shape[0], np.int64)
    if colour_manifolds(pair, dummy, colours) < 0:
        raise RuntimeError("more than 64 colours")
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
